"""The job server of a local run: one interpreter that imports the libraries once and forks a
child for each job, so that a job does not spend 0.5–1.5 s importing NumPy, pandas, SciPy and
Matplotlib before its first line of work (about a fifth of a default run's job time).

The Snakefile starts it at ``onstart`` for a local run of enough jobs and stops it when the run
ends. Every workflow script calls :func:`delegate` before its own imports; where ``make`` built
the environment, its start hook (:func:`install_hook`) has the job's interpreter delegate as it
starts, before the preamble Snakemake puts in front of the script (:func:`early`). The job's process
connects; the server forks a child, which puts itself in a process group of its own and sends its
pid; the job's process then hands over its argv, working folder, environment and standard streams
(file descriptors 0–2), and the child runs the same script file and sends back its exit status,
which the job's process exits with. A job Snakemake cancels (SIGTERM, SIGINT, SIGHUP) passes the
signal on to its child's process group, kills the group if its child has not ended within a
grace time, and waits for the child (not for the processes the child started). Its own process
group keeps a child out of the terminal's job control: Ctrl-Z stops Snakemake and the jobs'
processes, not the children. Where no server runs (a cluster job, a script run
by hand, a job of more than one thread), where it cannot be reached or does not answer within
its timeout, the script runs in the job's own process as before; a job started while the server
still imports waits for it (within the same timeout). A child killed by a signal
fails its job with status 1. Linux only (fork, Unix sockets that pass file descriptors).

Fork safety: the server starts no thread of its own and loads the native thread pools with one
thread; pyarrow's jemalloc keeps a background thread, which jemalloc's own fork handlers cover.
A child runs the interpreter's exit steps (non-daemon threads joined, atexit functions) before it
reports, as a fresh interpreter would.
"""

from __future__ import annotations

import gc
import importlib
import json
import os
import select
import signal
import socket
import struct
import sys

# The server's socket and how long a job waits for its child (seconds), in every job's
# environment.
ADDRESS = "EXOBENCH_JOB_SERVER"
TIMEOUT = "EXOBENCH_JOB_SERVER_TIMEOUT_S"
# How long a cancelled job lets its child end on the job's own signal before killing it.
GRACE = "EXOBENCH_JOB_SERVER_GRACE_S"
# The signals a job passes on to its child when Snakemake (or a terminal) ends it.
CANCEL = (signal.SIGTERM, signal.SIGINT, signal.SIGHUP)
# Set in a forked job, whose script then runs instead of delegating again.
CHILD = "EXOBENCH_FORKED_JOB"
# The folder of the workflow scripts the run's server runs (set by start() with the address).
SCRIPTS = "EXOBENCH_JOB_SCRIPTS"
# The interpreter's start hook (a .pth file in the environment's site-packages, written by
# install_hook): where a server runs, a job script hands its job over before Snakemake's preamble.
HOOK_FILE = "exobench-jobserver.pth"
HOOK = (f"import os; os.environ.get({SCRIPTS!r}) and "
        "__import__('exobench.plumbing.jobserver').plumbing.jobserver.early()")  # fmt: skip
# Imported first: what every job imports (the server accepts jobs from then on).
CORE = ("numpy", "pandas", "pyarrow.parquet", "snakemake.script", "exobench.plumbing.runner")
# Libraries the package imports inside functions (its rules' modules import them lazily).
LAZY = (
    "scipy.signal",
    "scipy.stats",
    "scipy.interpolate",
    "scipy.optimize",
    "scipy.special",
    "scipy.ndimage",
    "matplotlib.pyplot",
    "matplotlib.backends.backend_agg",
    "matplotlib.backends.backend_pdf",
    "fontTools.subset",
    "statsmodels.stats.multitest",
    "statsmodels.stats.proportion",
    "statsmodels.stats.weightstats",
    "statsmodels.stats.power",
    "statsmodels.formula.api",
)
# Native thread pools are sized when their library loads: the server loads them with one thread,
# as Snakemake runs a job of one thread (a job of more threads runs in its own process).
THREADS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
           "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS", "GOTO_NUM_THREADS")  # fmt: skip
# Longest Unix socket path the kernel takes (108 bytes with the terminating zero), with margin.
MAX_ADDRESS = 100
_INT = struct.Struct("!i")
_SERVERS: list = []


def supported() -> bool:
    """Whether this platform can run the server (Linux: fork, Unix sockets passing streams)."""
    return sys.platform.startswith("linux") and hasattr(socket, "send_fds")


def start(workflow, settings: dict) -> bool:
    """Start the server for a local run of at least ``settings['min_jobs']`` (> 0) jobs."""
    import subprocess
    import tempfile
    from pathlib import Path

    minimum = int(settings["min_jobs"])
    deployed = workflow.deployment_settings.deployment_method
    if not (workflow.local_exec and not workflow.touch and not deployed and supported()):
        return False
    jobs = list(workflow.dag.needrun_jobs())
    address = os.path.join(tempfile.gettempdir(), "exobench-jobs-XXXXXXXX", "socket")
    if not 0 < minimum <= len(jobs) or len(address) > MAX_ADDRESS:
        return False
    address = os.path.join(tempfile.mkdtemp(prefix="exobench-jobs-"), "socket")  # mode 0700
    folder = os.path.join(workflow.basedir, "workflow", "scripts")
    scripts = sorted({Path(job.rule.script).name for job in jobs if job.rule.script})
    command = [sys.executable, "-P", "-m", "exobench.plumbing.jobserver", address, folder, *scripts]
    server = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
    _SERVERS.append((server, os.path.dirname(address)))
    os.environ[ADDRESS] = address
    os.environ[SCRIPTS] = folder
    os.environ[TIMEOUT] = str(float(settings["accept_timeout_s"]))
    os.environ[GRACE] = str(float(settings["cancel_grace_s"]))
    return True


def stop(grace_s: float = 10.0) -> None:
    """Stop the run's server and remove its folder."""
    import shutil
    import subprocess

    for name in (ADDRESS, SCRIPTS, TIMEOUT, GRACE):
        os.environ.pop(name, None)
    while _SERVERS:
        server, folder = _SERVERS.pop()
        server.terminate()
        try:
            server.wait(timeout=grace_s)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
        shutil.rmtree(folder, ignore_errors=True)


def delegate() -> None:
    """Run this job's script in a child of the run's server and exit with its status, or return."""
    address = os.environ.get(ADDRESS)
    if not address or os.environ.get(CHILD):
        return
    try:
        threads = int(os.environ.get("OMP_NUM_THREADS") or 1)
    except ValueError:  # a list of levels: more than one thread
        threads = 2
    if threads > 1:
        return
    import time

    deadline = time.monotonic() + float(os.environ[TIMEOUT])  # set with the address by start()
    conn = _connect(address, deadline)
    try:
        conn.settimeout(max(deadline - time.monotonic(), 0.01))
        hello = _read(conn, _INT.size)  # the child's pid: it takes the job from here on
    except OSError:  # no server, not accepting in time, or no child in time: the job runs here
        hello = None
    if hello is None:
        conn.close()
        return
    child = _INT.unpack(hello)[0]
    ignored = [int(s) for s in CANCEL if signal.getsignal(s) is signal.SIG_IGN]
    conn.settimeout(None)
    request = json.dumps({"argv": sys.argv, "cwd": os.getcwd(), "env": dict(os.environ),
                          "ignored": ignored}).encode()  # fmt: skip
    try:
        socket.send_fds(conn, [_INT.pack(len(request))], [0, 1, 2])
        conn.sendall(request)
    except OSError:  # the child cannot have the whole request: it ends, the job runs here
        conn.close()
        return

    grace_s = float(os.environ[GRACE])

    def cancel(signum, _frame):  # Snakemake ends the job: so is the child, then this process
        _end_group(child, signum, grace_s)
        os._exit(128 + signum)

    for signum in CANCEL:
        if signum not in ignored:
            signal.signal(signum, cancel)
    status = _read(conn, _INT.size)
    conn.close()
    if status is None:
        print("the job's forked process ended without an exit status", file=sys.stderr)
        os._exit(1)
    os._exit(_INT.unpack(status)[0])


def early() -> None:
    """Delegate at the interpreter's start (the start hook calls this while a server runs) when
    the interpreter runs Snakemake's copy of a served script (``.snakemake/scripts/tmp….<name>``,
    ``<name>`` in the server's folder): the job's process then never runs Snakemake's preamble,
    which imports Snakemake (0.13 s of CPU a job); the child runs the whole copy as before. One
    try only (a virtual environment reads its .pth files twice): a job that was not handed over
    runs in its own process without asking again; Ctrl-C meanwhile ends it as Ctrl-C would."""
    folder = os.environ.pop(SCRIPTS, "")
    script = os.path.abspath(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    copies = os.path.dirname(script)
    name = os.path.basename(script).split(".", 1)[-1]
    snakemake = (os.path.basename(copies), os.path.basename(os.path.dirname(copies)))
    if snakemake != ("scripts", ".snakemake") or not name.endswith(".py"):
        return
    if not (folder and os.path.isfile(os.path.join(folder, name))):
        return
    try:
        delegate()
    except KeyboardInterrupt:  # the start-up would end in a fatal error: end by the signal
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGINT)
    os.environ.pop(ADDRESS, None)  # not handed over: the script's own delegate() returns


def install_hook(folder: str | None = None) -> str:
    """Write the start hook (:data:`HOOK`) into ``folder`` (this environment's site-packages)."""
    import sysconfig

    path = os.path.join(folder or sysconfig.get_paths()["purelib"], HOOK_FILE)
    with open(path, "w", encoding="utf-8") as hook:
        hook.write(HOOK + "\n")
    return path


def _connect(address: str, deadline: float) -> socket.socket:
    """A socket connected to the server at ``address``, or unconnected (reading fails) when none
    answers: while the server's folder exists and its socket is not yet bound (the run's first
    jobs start while the server imports its core libraries), tried again until ``deadline``
    (time.monotonic). A job that waits for the server's imports spares the run its own (2–4 s
    on a core that the server and the other first job share)."""
    import time

    while True:
        conn = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        conn.settimeout(max(deadline - time.monotonic(), 0.01))
        try:
            conn.connect(address)
            return conn
        except FileNotFoundError:  # not bound yet, or no server (no folder either)
            starting = os.path.isdir(os.path.dirname(address))
            if not starting or time.monotonic() >= deadline:
                return conn
        except OSError:  # refused: a server that ended without removing its socket
            return conn
        conn.close()
        time.sleep(0.02)


def _end_group(pid: int, signum: int, grace_s: float) -> None:
    """Send ``signum`` to process group ``pid``, SIGKILL after ``grace_s``; wait for its leader."""
    import time

    for sent, wait_s in ((signum, grace_s), (signal.SIGKILL, grace_s)):
        try:
            os.killpg(pid, sent)
        except ProcessLookupError:
            return
        deadline = time.monotonic() + wait_s
        while time.monotonic() < deadline:
            if not _alive(pid):
                return
            time.sleep(0.01)


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, ended but not reaped, does not)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (FileNotFoundError, ProcessLookupError, IndexError):
        return False


def _read(conn: socket.socket, size: int) -> bytes | None:
    """Exactly ``size`` bytes from a connection, None when it closes before."""
    data = b""
    while len(data) < size:
        block = conn.recv(size - len(data))
        if not block:
            return None
        data += block
    return data


def script_modules(folder: str, scripts: list[str]) -> list[str]:
    """The package modules the named workflow scripts import directly."""
    from pathlib import Path

    from exobench.plumbing import codedeps

    names = set()
    for script in scripts:
        names |= codedeps.imported_names(Path(folder) / script)
    return sorted(n for n in names if n.startswith("exobench") and codedeps.module_file(n))


def _load(name: str) -> None:
    """Import a module for the children (one that fails is left to the job that needs it)."""
    try:
        importlib.import_module(name)
    except Exception:  # the job imports it again and reports what fails
        return
    gc.freeze()  # what is loaded stays shared with the children: their collections skip it


def serve(address: str, folder: str, scripts: list[str], lazy: tuple[str, ...] = LAZY) -> None:
    """Import, then fork a child per connection until SIGTERM or the parent's end."""
    parent = os.getppid()
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(0))
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C reaches the jobs, not the server
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        for name in THREADS:
            os.environ[name] = "1"
        for name in CORE:
            _load(name)
        pending = [*script_modules(folder, scripts), *lazy]
        signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # the kernel reaps the children
        listener.bind(address)
        listener.listen(64)
        while os.getppid() == parent:
            ready, _, _ = select.select([listener], [], [], 0.0 if pending else 1.0)
            if not ready:
                if pending:
                    _load(pending.pop(0))
                continue
            conn, _ = listener.accept()
            if _same_user(conn):
                _fork(listener, conn)
            conn.close()
    finally:
        listener.close()
        if os.path.exists(address):
            os.unlink(address)
        os.rmdir(os.path.dirname(address))


def _fork(listener: socket.socket, conn: socket.socket) -> None:
    """Fork a child for the job at ``conn`` (the job runs itself when the fork fails)."""
    try:
        pid = os.fork()
    except OSError:
        return
    if pid == 0:
        try:
            listener.close()
            _child(conn)
        except BaseException:  # the child failed before or after the script: say why
            import traceback

            traceback.print_exc()
        finally:
            os._exit(1)  # never back into the server's loop


def _same_user(conn: socket.socket) -> bool:
    """Whether the peer runs as this process's user."""
    creds = conn.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, struct.calcsize("3i"))
    return struct.unpack("3i", creds)[1] == os.getuid()


def _child(conn: socket.socket) -> None:
    """Take a job's streams, folder and environment, run its script and send its exit status."""
    import atexit
    import runpy
    import tempfile
    import threading
    import traceback

    for signum in (signal.SIGCHLD, signal.SIGTERM):
        signal.signal(signum, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.default_int_handler)  # the server ignores it
    os.setpgid(0, 0)  # the job's process ends this group when the job is cancelled
    try:
        conn.sendall(_INT.pack(os.getpid()))
    except OSError:  # the job gave up waiting and runs itself
        os._exit(0)
    header, fds, _, _ = socket.recv_fds(conn, _INT.size, 3)
    if not header:  # the job gave up waiting and runs itself
        os._exit(0)
    header += _read(conn, _INT.size - len(header)) or b""
    request = json.loads(_read(conn, _INT.unpack(header)[0]) or b"{}")
    for signum in request["ignored"]:  # as the job's own process had them
        signal.signal(signum, signal.SIG_IGN)
    _take_streams(fds, bool(request["env"].get("PYTHONUNBUFFERED")))
    os.chdir(request["cwd"])
    os.environ.clear()
    os.environ.update(request["env"], **{CHILD: "1"})
    tempfile.tempdir = None  # the job's TMPDIR
    sys.argv = list(request["argv"])
    sys.path[0:0] = [os.path.dirname(os.path.abspath(sys.argv[0]))]  # as `python script.py`

    def watch() -> None:  # the job's process is gone without cancelling: end this one
        _read(conn, 1)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()
    code = 0
    try:
        runpy.run_path(sys.argv[0], run_name="__main__")
    except SystemExit as end:
        code = end.code if isinstance(end.code, int) else int(end.code is not None)
        if end.code is not None and not isinstance(end.code, int):
            print(end.code, file=sys.stderr)
    except KeyboardInterrupt:
        code = 128 + signal.SIGINT
    except BaseException:  # reported as Python reports an uncaught error
        traceback.print_exc()
        code = 1
    threading._shutdown()  # the interpreter's exit steps: join threads, run atexit functions,
    atexit._run_exitfuncs()
    gc.collect()  # and close what the script left open
    sys.stdout.flush()
    sys.stderr.flush()
    conn.sendall(_INT.pack(code))
    os._exit(code)


def _take_streams(fds: list[int], unbuffered: bool) -> None:
    """Make the job's descriptors 0–2 this process's, with a fresh interpreter's text streams."""
    import io

    for target, fd in enumerate(fds):
        os.dup2(fd, target)
        os.close(fd)
    out, err = sys.__stdout__, sys.__stderr__  # the server's: same locale, same settings

    def stream(fd: int, like, line: bool) -> io.TextIOWrapper:
        raw = io.BufferedWriter(io.FileIO(fd, "w", closefd=False))
        buffering = {"line_buffering": line or unbuffered, "write_through": unbuffered}
        return io.TextIOWrapper(raw, encoding=like.encoding, errors=like.errors, **buffering)

    sys.stdin = open(0, closefd=False, encoding=out.encoding, errors=out.errors)
    sys.stdout = sys.__stdout__ = stream(1, out, os.isatty(1))
    sys.stderr = sys.__stderr__ = stream(2, err, True)


if __name__ == "__main__":
    serve(sys.argv[1], sys.argv[2], sys.argv[3:])
