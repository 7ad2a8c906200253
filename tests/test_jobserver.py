"""The job server: a job delegated to it runs in a forked child with the job's streams, folder,
environment and exit status; a cancelled job ends its child; without a server the script runs in
its own process; every workflow script delegates before its own imports."""

from __future__ import annotations

import ast
import json
import os
import signal
import socket
import subprocess
import sys
import sysconfig
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

from exobench.plumbing import jobserver

REPO = Path(__file__).resolve().parents[1]
# The job server's settings as the config gives them (start() puts the times in the environment).
SETTINGS = {"accept_timeout_s": 10.0, "cancel_grace_s": 5.0}
# A job's script: delegates, then records where it ran and ends as its arguments say.
PROBE = """
import os, sys
from exobench.plumbing import jobserver

jobserver.delegate()

import json, pathlib, signal, time

record, action = sys.argv[1], sys.argv[2]
pathlib.Path(record).write_text(json.dumps({"pid": os.getpid(), "cwd": os.getcwd(),
                                            "probe": os.environ.get("PROBE")}))
print("to stdout")
print("to stderr", file=sys.stderr)
if action == "busy":  # one long call without Python in between: no signal handler runs
    sum(range(10**10))
if action == "wait":  # Python waiting: Ctrl-C's KeyboardInterrupt runs the cleanup
    try:
        time.sleep(60)
    finally:
        pathlib.Path(record).with_suffix(".cleaned").write_text("cleaned")
if action == "crash":
    os.kill(os.getpid(), signal.SIGKILL)
if action == "raise":
    raise ValueError("a bad value")
sys.exit(int(action))
"""


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """A server with only the core imports (no scripts, nothing lazy), for this module."""
    if not jobserver.supported():
        pytest.skip("the job server runs on Linux only")
    folder = tmp_path_factory.mktemp("server")
    address = folder / "sock" / "socket"
    address.parent.mkdir()
    process = _serve(address)
    deadline = time.monotonic() + 60
    while True:  # ready once it accepts
        probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            probe.connect(str(address))
            break
        except OSError:
            assert process.poll() is None and time.monotonic() < deadline, "no server"
            time.sleep(0.05)
        finally:
            probe.close()
    yield address
    process.terminate()
    assert process.wait(timeout=30) == 0
    assert not address.exists()  # the server removed its socket


def _serve(address: Path) -> subprocess.Popen:
    """A server at ``address`` (its folder made) importing only its core libraries."""
    code = f"from exobench.plumbing import jobserver; jobserver.serve({str(address)!r}, " \
           f"{str(address.parent)!r}, [], lazy=())"  # fmt: skip
    return subprocess.Popen([sys.executable, "-c", code])


def _job_env(address, threads: str = "1", **extra) -> dict:
    """A job's environment: the server's address and times as start() sets them (no address
    where ``address`` is None), its threads, the probe's variable and ``extra``."""
    server = {
        jobserver.TIMEOUT: str(SETTINGS["accept_timeout_s"]),
        jobserver.GRACE: str(SETTINGS["cancel_grace_s"]),
    }
    env = {**os.environ, "PROBE": "from the job", "OMP_NUM_THREADS": threads, **server, **extra}
    env.pop(jobserver.ADDRESS, None)
    if address is not None:
        env[jobserver.ADDRESS] = str(address)
    return env


def _job(tmp_path: Path, address, action: str, threads: str = "1", **extra) -> subprocess.Popen:
    """Start the probe script as Snakemake would start a job (its own process and streams)."""
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    env = _job_env(address, threads, **extra)
    work = tmp_path / "work"
    work.mkdir(exist_ok=True)
    return subprocess.Popen([sys.executable, str(script), str(tmp_path / "record.json"), action],
                            cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)  # fmt: skip


def _record(tmp_path: Path) -> dict:
    """What the probe recorded: its pid, folder and PROBE variable."""
    return json.loads((tmp_path / "record.json").read_text())


def test_a_delegated_job_runs_in_a_child_with_its_streams_folder_environment_and_status(
    server, tmp_path
):
    job = _job(tmp_path, server, "3")
    out, err = job.communicate(timeout=60)
    record = _record(tmp_path)
    assert job.returncode == 3
    assert (out, err) == ("to stdout\n", "to stderr\n")
    assert record["pid"] != job.pid  # run by the server's child, not the job's process
    assert record["cwd"] == str(tmp_path / "work")
    assert record["probe"] == "from the job"


@pytest.mark.parametrize("address", [None, "missing/socket"])
def test_without_a_server_the_script_runs_in_its_own_process(tmp_path, address):
    job = _job(tmp_path, address and tmp_path / address, "0")
    out, _ = job.communicate(timeout=60)
    assert job.returncode == 0 and out == "to stdout\n"
    assert _record(tmp_path)["pid"] == job.pid


def test_a_job_started_while_the_server_imports_waits_for_it(tmp_path):
    address = tmp_path / "sock" / "socket"
    address.parent.mkdir()  # start() makes the folder before the server binds its socket
    job = _job(tmp_path, address, "0")
    time.sleep(0.5)  # the job is waiting by now
    server = _serve(address)
    try:
        out, _ = job.communicate(timeout=60)
        assert job.returncode == 0 and out == "to stdout\n"
        assert _record(tmp_path)["pid"] != job.pid  # run by the server's child
    finally:
        server.terminate()
        server.wait(timeout=30)


def test_an_uncaught_error_is_reported_and_fails_the_job(server, tmp_path):
    job = _job(tmp_path, server, "raise")
    _, err = job.communicate(timeout=60)
    assert job.returncode == 1
    assert "ValueError: a bad value" in err and "Traceback" in err


def test_a_child_killed_by_a_signal_fails_the_job(server, tmp_path):
    job = _job(tmp_path, server, "crash")
    _, err = job.communicate(timeout=60)
    assert job.returncode == 1
    assert "without an exit status" in err


def _wait_for_record(tmp_path: Path, job: subprocess.Popen) -> int:
    """The probe's pid once it has recorded it (it runs its action then)."""
    deadline = time.monotonic() + 60
    while not (tmp_path / "record.json").exists():
        assert time.monotonic() < deadline and job.poll() is None
        time.sleep(0.05)
    time.sleep(0.1)  # past the record's write, into the action
    return _record(tmp_path)["pid"]


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_cancelled_job_has_ended_its_busy_child_when_it_exits(server, tmp_path, signum):
    job = _job(tmp_path, server, "busy", **{jobserver.GRACE: "0.5"})
    child = _wait_for_record(tmp_path, job)
    job.send_signal(signum)
    job.communicate(timeout=60)
    assert job.returncode == 128 + signum
    assert not jobserver._alive(child)


def test_ctrl_c_lets_the_child_clean_up_as_a_fresh_interpreter_would(server, tmp_path):
    job = _job(tmp_path, server, "wait", **{jobserver.GRACE: "30"})
    child = _wait_for_record(tmp_path, job)
    job.send_signal(signal.SIGINT)
    job.communicate(timeout=60)
    assert job.returncode == 128 + signal.SIGINT
    assert (tmp_path / "record.cleaned").read_text() == "cleaned"
    assert not jobserver._alive(child)


def _silent_server(address: Path) -> socket.socket:
    """A listening socket at ``address`` that accepts connections and never forks a child."""
    silent = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    silent.bind(str(address))
    silent.listen(8)
    return silent


def test_a_job_whose_child_does_not_answer_in_time_runs_itself(tmp_path):
    address = tmp_path / "silent.sock"
    silent = _silent_server(address)
    try:
        job = _job(tmp_path, address, "0", **{jobserver.TIMEOUT: "0.3"})
        out, _ = job.communicate(timeout=60)
    finally:
        silent.close()
    assert job.returncode == 0 and out == "to stdout\n"
    assert _record(tmp_path)["pid"] == job.pid


def test_a_job_of_several_threads_runs_in_its_own_process(server, tmp_path):
    job = _job(tmp_path, server, "0", threads="2")
    job.communicate(timeout=60)
    assert job.returncode == 0 and _record(tmp_path)["pid"] == job.pid


# Snakemake's preamble stand-in: what runs before the script's own lines, in whichever process.
PREAMBLE = """import os, pathlib, sys
pathlib.Path(sys.argv[1]).with_suffix(f".preamble.{os.getpid()}").touch()
"""


def _hooked_start(tmp_path: Path, address, copy: str, code: str = "0", **extra):
    """Start Snakemake's copy ``.snakemake/scripts/<copy>`` of the probe (preamble first) with an
    interpreter whose site-packages holds the start hook, the served scripts (``probe.py``) in
    ``served/``."""
    env_dir = tmp_path / "env"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(env_dir)], check=True)
    site = next(env_dir.glob("lib/python*/site-packages"))
    assert Path(jobserver.install_hook(str(site))).read_text() == jobserver.HOOK + "\n"
    (tmp_path / "served").mkdir()
    (tmp_path / "served" / "probe.py").write_text(PROBE)
    work = tmp_path / "work"
    copies = work / ".snakemake" / "scripts"
    copies.mkdir(parents=True)
    (copies / copy).write_text(PREAMBLE + PROBE)
    env = _job_env(address, **{jobserver.SCRIPTS: str(tmp_path / "served"),
                               "PYTHONPATH": os.pathsep.join(sys.path), **extra})  # fmt: skip
    return subprocess.Popen([str(env_dir / "bin" / "python"), f".snakemake/scripts/{copy}",
                             str(tmp_path / "record.json"), code], cwd=work, env=env,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip


def _ended(job: subprocess.Popen) -> tuple[int, str]:
    """A job's exit status and standard error once it ends (killed if it does not within 2 min)."""
    try:
        _, err = job.communicate(timeout=120)
    finally:
        job.kill()
    return job.returncode, err


def _preambles(tmp_path: Path) -> set[int]:
    """The pids of the processes that ran the probe's preamble."""
    return {int(p.suffix[1:]) for p in tmp_path.glob("record.preamble.*")}


@pytest.mark.parametrize(("copy", "early"), [("tmpab12cd.probe.py", True),
                                             ("tmpab12cd.other.py", False)])  # fmt: skip
def test_the_start_hook_hands_a_served_script_over_before_snakemakes_preamble(
    server, tmp_path, copy, early
):
    job = _hooked_start(tmp_path, server, copy, "4")
    status, _ = _ended(job)
    child = _record(tmp_path)["pid"]
    assert status == 4 and child != job.pid  # forked by the server either way
    # a served script's copy runs the preamble in the child only, another one in both
    assert _preambles(tmp_path) == ({child} if early else {job.pid, child})


def test_a_job_the_server_does_not_take_at_start_asks_once_and_runs_itself(tmp_path):
    address = tmp_path / "silent.sock"
    silent = _silent_server(address)
    try:
        job = _hooked_start(tmp_path, address, "tmpab12cd.probe.py", **{jobserver.TIMEOUT: "0.5"})
        status, _ = _ended(job)
        asked = 0
        silent.settimeout(0.1)
        while True:  # the connections the job made (a venv reads its .pth files twice)
            try:
                silent.accept()[0].close()
                asked += 1
            except TimeoutError:
                break
    finally:
        silent.close()
    assert status == 0 and _record(tmp_path)["pid"] == job.pid
    assert asked == 1 and _preambles(tmp_path) == {job.pid}


def test_ctrl_c_while_a_job_waits_for_the_server_at_start_ends_it_by_the_signal(tmp_path):
    address = tmp_path / "sock" / "socket"
    address.parent.mkdir()  # a server that is still importing: the job waits for its socket
    job = _hooked_start(tmp_path, address, "tmpab12cd.probe.py")
    time.sleep(1.0)  # waiting by now
    job.send_signal(signal.SIGINT)
    status, err = _ended(job)
    assert status == -signal.SIGINT and "Fatal Python error" not in err
    assert not (tmp_path / "record.json").exists()


def test_the_environment_make_builds_has_the_start_hook():
    if Path(sys.prefix) != REPO / ".venv":
        pytest.skip("tests run outside the environment make builds")
    site = Path(sysconfig.get_paths()["purelib"])
    assert (site / jobserver.HOOK_FILE).read_text() == jobserver.HOOK + "\n"


def _workflow(jobs: int, local=True, touch=False, deployed=()) -> SimpleNamespace:
    """A stand-in for Snakemake's workflow object: what :func:`jobserver.start` reads."""
    rule = SimpleNamespace(script="../scripts/sts_beam.py")
    dag = SimpleNamespace(needrun_jobs=lambda: iter([SimpleNamespace(rule=rule)] * jobs))
    deployment = SimpleNamespace(deployment_method=set(deployed))
    return SimpleNamespace(local_exec=local, touch=touch, dag=dag, basedir=str(REPO),
                           deployment_settings=deployment)  # fmt: skip


NO_SERVER = {
    "cluster": (_workflow(20, local=False), 8),
    "touch": (_workflow(20, touch=True), 8),
    "container": (_workflow(20, deployed=["apptainer"]), 8),
    "few-jobs": (_workflow(7), 8),
    "off": (_workflow(20), 0),
}


@pytest.mark.parametrize(("workflow", "minimum"), NO_SERVER.values(), ids=NO_SERVER.keys())
def test_no_server_for_a_cluster_touch_container_small_run_or_when_off(workflow, minimum):
    assert jobserver.start(workflow, {**SETTINGS, "min_jobs": minimum}) is False
    assert jobserver.ADDRESS not in os.environ


def test_a_started_server_serves_the_run_and_its_folder_goes_with_it(tmp_path):
    if not jobserver.supported():
        pytest.skip("the job server runs on Linux only")
    assert jobserver.start(_workflow(20), {**SETTINGS, "min_jobs": 8}) is True
    address = Path(os.environ[jobserver.ADDRESS])
    try:
        deadline = time.monotonic() + 120
        while True:  # a job waits for the server within its timeout, then runs itself
            job = _job(tmp_path, address, "0")
            job.communicate(timeout=120)
            assert job.returncode == 0
            if _record(tmp_path)["pid"] != job.pid:
                break
            assert time.monotonic() < deadline, "no job was forked by the started server"
            time.sleep(0.2)
    finally:
        jobserver.stop()
    assert jobserver.ADDRESS not in os.environ and not address.parent.exists()


def test_script_modules_are_the_package_modules_the_scripts_import(tmp_path):
    (tmp_path / "a.py").write_text("from exobench.phantom.chain import filtering, metrics\n")
    (tmp_path / "b.py").write_text("from exobench import tables\nimport numpy\n")
    (tmp_path / "c.py").write_text("from exobench.plumbing import provenance as p\n")
    assert jobserver.script_modules(str(tmp_path), ["a.py", "b.py"]) == [
        "exobench", "exobench.phantom.chain", "exobench.phantom.chain.filtering",
        "exobench.phantom.chain.metrics", "exobench.tables"]  # fmt: skip
    assert "exobench.plumbing.provenance" in jobserver.script_modules(str(tmp_path), ["c.py"])


def _delegates_first(path: Path) -> bool:
    """Whether a script calls ``jobserver.delegate()`` before any import but ``os`` and the
    job server's own."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Expr) and ast.unparse(node) == "jobserver.delegate()":
            return True
        if isinstance(node, ast.Import) and [a.name for a in node.names] != ["os"]:
            return False
        if isinstance(node, ast.ImportFrom) and ast.unparse(node) != (
            "from exobench.plumbing import jobserver"
        ):
            return False
    return False


def test_every_workflow_script_delegates_before_its_imports():
    scripts = sorted((REPO / "workflow" / "scripts").glob("*.py"))
    assert scripts
    assert [p.name for p in scripts if not _delegates_first(p)] == []
