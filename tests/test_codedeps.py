"""Code params: the package files a script imports, found by parsing, transitively, and their
digest; a job whose files changed after the DAG was built stops."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from conftest import REPO
from exobench.plumbing import codedeps, provenance, runner


def _package(root: Path) -> Path:
    """A small exobench package: a imports b lazily, b imports c relatively, d is unused."""
    pkg = root / "exobench"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text('"""Package."""\n')
    (pkg / "sub" / "__init__.py").write_text("from . import c\n")
    (pkg / "a.py").write_text("import numpy\n\ndef f():\n    from exobench.sub import b\n")
    (pkg / "sub" / "b.py").write_text("from .c import VALUE\n")
    (pkg / "sub" / "c.py").write_text("VALUE = 1\n")
    (pkg / "d.py").write_text("import exobench.a\n")
    return pkg


def test_transitive_relative_and_lazy_imports_are_found(tmp_path):
    pkg = _package(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("import os\nfrom exobench import a\n")
    found = codedeps.code_files(script, pkg)
    names = sorted(p.relative_to(pkg).as_posix() for p in found)
    assert names == ["__init__.py", "a.py", "sub/__init__.py", "sub/b.py", "sub/c.py"]


def test_a_package_that_loads_its_modules_by_name_runs_every_one_of_them(tmp_path):
    pkg = _package(tmp_path)
    lazy = pkg / "lazy"
    lazy.mkdir()
    (lazy / "__init__.py").write_text(
        "from importlib import import_module\n\n"
        "def __getattr__(name):\n    return import_module(f'{__name__}.{name}')\n"
    )
    (lazy / "engine.py").write_text("from exobench.sub import c\n")
    script = tmp_path / "script.py"
    script.write_text("from exobench import lazy\n")
    names = sorted(p.relative_to(pkg).as_posix() for p in codedeps.code_files(script, pkg))
    assert names == ["__init__.py", "lazy/__init__.py", "lazy/engine.py", "sub/__init__.py",
                     "sub/c.py"]  # fmt: skip


def test_the_engine_s_rules_run_the_modules_its_package_loads_by_name():
    for script in ("phantom_discrepancy.py", "emulator_discrepancy.py"):
        files = codedeps.code_param(REPO / "workflow" / "scripts" / script)["files"]
        assert {"exobench/selection/report.py", "exobench/selection/blocks.py"} <= set(files)


def test_a_script_without_package_imports_runs_no_package_file(tmp_path):
    pkg = _package(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("import json\n")
    assert codedeps.code_files(script, pkg) == []


def test_the_code_param_names_the_files_and_changes_with_any_of_their_bytes(tmp_path):
    pkg = _package(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("from exobench import a\n")
    before = codedeps.code_param(script, pkg)
    assert before["files"] == [
        f"exobench/{name}"
        for name in ("__init__.py", "a.py", "sub/__init__.py", "sub/b.py", "sub/c.py")
    ]
    unused = pkg / "d.py"
    unused.write_text(unused.read_text() + "# edited\n")
    assert codedeps.code_param(script, pkg) == before  # a module the script never runs
    used = pkg / "sub" / "c.py"
    used.write_text("VALUE = 2\n")
    after = codedeps.code_param(script, pkg)
    assert after["files"] == before["files"] and after["sha256"] != before["sha256"]


class _Job:
    """What a ``script:`` job's ``snakemake`` object gives the runner (no inputs, no log)."""

    def __init__(self, code: dict):
        self.rule, self.input, self.log, self.config = "toy", [], [], {}
        self.params = type("Params", (dict,), {"__getattr__": dict.__getitem__})(code=code)


def test_a_job_whose_modules_changed_after_the_dag_was_built_stops(caplog):
    script = REPO / "workflow" / "scripts" / "results_index.py"
    planned = codedeps.code_param(script)
    ran = []
    runner.run(_Job(planned), lambda smk, record: ran.append(record["code_sha256"]))
    assert ran == [planned["sha256"]]
    stale = {**planned, "sha256": "0" * 64}  # as if a module was edited since the DAG was built
    with pytest.raises(SystemExit) as stop:
        runner.run(_Job(stale), lambda smk, record: ran.append("ran anyway"))
    assert stop.value.code == 2 and ran == [planned["sha256"]]
    assert f"bad input: {provenance.PACKAGE_ROOT}: field 'code'" in caplog.text
    assert "run Snakemake again" in caplog.text
    gone = {**planned, "files": [*planned["files"], "exobench/removed_since.py"]}
    with pytest.raises(SystemExit) as stop:  # a module deleted or renamed since: no traceback
        runner.run(_Job(gone), lambda smk, record: ran.append("ran anyway"))
    assert stop.value.code == 2 and ran == [planned["sha256"]]


def test_the_code_param_is_the_same_from_a_copy_of_the_package(tmp_path):
    # as the tests' runs import a copy (PYTHONPATH): the same files, the same digest
    copy = tmp_path / "elsewhere" / "exobench"
    shutil.copytree(codedeps.PACKAGE_ROOT, copy, ignore=shutil.ignore_patterns("__pycache__"))
    script = REPO / "workflow" / "scripts" / "phantom_chain.py"
    assert codedeps.code_param(script, copy) == codedeps.code_param(script)


def test_every_workflow_script_depends_on_the_runner_and_its_own_modules():
    scripts = sorted((REPO / "workflow" / "scripts").glob("*.py"))
    assert scripts
    root = codedeps.PACKAGE_ROOT
    for script in scripts:
        names = {p.relative_to(root).as_posix() for p in codedeps.code_files(script)}
        assert {
            "plumbing/runner.py",
            "plumbing/provenance.py",
            "errors.py",
            "__init__.py",
        } <= names, script
    filtering = {
        p.relative_to(root).as_posix()
        for p in codedeps.code_files(REPO / "workflow" / "scripts" / "phantom_chain.py")
    }
    assert "phantom/chain/filtering.py" in filtering
    assert "phantom/model/discrepancy.py" not in filtering
    assert not any(name.startswith(("sts/", "emulator/")) for name in filtering)


# The twins make the test data: the code they run, import by import, may be the rig contract, file
# writing and checking, and their own modules, never the analysis or the discrepancy engines
# (which would then agree with them by construction). The phantom's file contract (c3d) reads as
# well as writes, and reading resamples a lab's rates to the analysis rates (resample, with the
# shared low-pass of signals).
TWINS = {
    "phantom": {
        "twin/__init__",
        "twin/twin",
        "twin/twin_mechanics",
        "twin/trajectory",
        "rig",
        "recordings/__init__",
        "recordings/c3d",
        "recordings/resample",
    },
    "emulator": {"twin/__init__", "twin/twin", "twin/twin_loop", "twin/gait", "rig"},
}
READING = {"phantom": {"signals"}, "emulator": set()}  # shared modules the file contract imports
TWIN_MODULES = {"phantom": "exobench.phantom.twin.twin", "emulator": "exobench.emulator.twin.twin"}
INFRASTRUCTURE = {"__init__", "atomic", "plumbing/__init__", "plumbing/stamp", "tables", "errors",
                  "csvfiles", "plausibility", "plumbing/provenance"}  # fmt: skip


@pytest.mark.parametrize("group", sorted(TWINS))
def test_twins_run_no_analysis_code(group):
    allowed = (
        INFRASTRUCTURE | READING[group] | {f"{group}/{m}" for m in TWINS[group] | {"__init__"}}
    )
    twin = codedeps.module_file(TWIN_MODULES[group])
    ran = {f.relative_to(codedeps.PACKAGE_ROOT).with_suffix("").as_posix()
           for f in codedeps.code_files(twin)}  # fmt: skip
    assert f"{group}/rig" in ran  # the chain is seen
    assert ran <= allowed, sorted(ran - allowed)
