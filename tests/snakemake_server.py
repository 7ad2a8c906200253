"""The Snakemake command line for the tests, started by fork from a process that has imported it.

A ``snakemake`` process spends about 1.4 s of its 2.5 s dry run importing Snakemake and finding
its plugins before it reads the Snakefile. This server does that once (per pytest worker,
:func:`conftest.snakemake`), then for each request forks a child that becomes the command line:
it takes the request's folder, environment (``PYTHONPATH`` first on the import path, as a new
interpreter would put it), argument list and output files, and runs ``snakemake.cli.main`` — the
function the ``snakemake`` script runs — to its exit. The Snakefile, the package and every job
are imported and run in the child (or in the processes it starts), as in a fresh command line.
What the child cannot take from the request is the interpreter's own start-up state: its hash
seed, flags and warning filters are the server's (``PYTHONHASHSEED`` or ``PYTHONWARNINGS`` in a
request's environment do not apply; the jobs it starts are new interpreters and do take them).

Requests: one JSON line on stdin each, ``{"cwd", "env", "args", "stdout", "stderr"}``; the reply
is the child's exit code on a line of stdout. The server ends at the end of its stdin.
"""

from __future__ import annotations

import json
import os
import sys
import traceback
from pathlib import Path

# as the console script: its own folder first on the import path, not this test folder
sys.path[0] = str(Path(sys.executable).parent)

import snakemake.cli  # noqa: E402
from snakemake_interface_executor_plugins.registry import ExecutorPluginRegistry  # noqa: E402
from snakemake_interface_report_plugins.registry import ReportPluginRegistry  # noqa: E402
from snakemake_interface_storage_plugins.registry import StoragePluginRegistry  # noqa: E402

SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))


def command_line(request: dict) -> None:
    """Become ``snakemake <args>`` run in ``cwd`` with ``env``; exit with its exit code."""
    os.chdir(request["cwd"])
    os.environ.clear()
    os.environ.update(request["env"])
    extra = [p for p in request["env"].get("PYTHONPATH", "").split(os.pathsep) if p]
    sys.path[1:1] = extra
    null = os.open(os.devnull, os.O_RDONLY)
    os.dup2(null, 0)
    os.close(null)
    for fd, name in ((1, "stdout"), (2, "stderr")):
        out = os.open(request[name], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        os.dup2(out, fd)
        os.close(out)
    sys.argv = [SNAKEMAKE, *request["args"]]
    try:
        snakemake.cli.main()
    except SystemExit:
        raise
    except BaseException:
        traceback.print_exc()
        sys.exit(1)
    sys.exit(0)  # main() exits itself today; a child must never fall back into the server's loop


def serve() -> None:
    """Fork a command line per request line; reply with its exit code."""
    for registry in (ExecutorPluginRegistry, StoragePluginRegistry, ReportPluginRegistry):
        registry()  # found once here, not in every child
    for line in sys.stdin:
        request = json.loads(line)
        pid = os.fork()
        if pid == 0:
            command_line(request)
        _, status = os.waitpid(pid, 0)
        print(os.waitstatus_to_exitcode(status), flush=True)


if __name__ == "__main__":
    serve()
