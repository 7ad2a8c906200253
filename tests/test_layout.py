"""The package's layout, read from its import graph (parsed, never imported): no cycles, no module
importing from a later stage, a root that holds only what the groups share, and independent
generators that share no code with the analysis."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from exobench.plumbing import codedeps

ROOT = codedeps.PACKAGE_ROOT
GROUPS = ("phantom", "sts", "emulator")
# The package's layers, earliest first: what every group shares (the root and the workflow's
# plumbing), the model-selection engine, then the groups, which never import one another.
LAYERS = {"": 0, "plumbing": 0, "selection": 1, **dict.fromkeys(GROUPS, 2)}
# A group's stages, earliest first; "" is the group's own modules (its rig, reference data).
# A group's config rules check settings of every stage, so they come last.
STAGES = ("", "recordings", "chain", "study", "twin", "model", "report", "validation")
LAST = {"config_rules"}
# The independent recording generators: written from docs/rig.md and the physics alone.
GENERATORS = ("phantom.validation.labsim", "emulator.validation.labsim")
SCRIPTS = codedeps.PACKAGE_ROOT.parents[1] / "workflow" / "scripts"
# The validation rules' scripts, by the group whose engine they validate ("selection": the
# shared engine, on every group's twin).
VALIDATION_SCRIPTS = {"validate_discrepancy": "phantom", "validate_openworld": "phantom",
                      "validate_emulator": "emulator",
                      "validate_stability": "selection"}  # fmt: skip
# Rules of the whole run, of no group (the results folder's index): their scripts import only
# the package root and its plumbing.
SHARED_SCRIPTS = {"results_index"}


def module_name(path: Path) -> str:
    """Dotted name of a package file, without the leading ``exobench``."""
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(path): path for path in sorted(ROOT.rglob("*.py"))}


def imports(name: str) -> set[str]:
    """The package modules a module imports (anywhere in it), by dotted name."""
    found = set()
    for dotted in codedeps.imported_names(MODULES[name]):
        parts = dotted.split(".")
        if parts[0] != "exobench":
            continue
        inner = ".".join(parts[1:])
        while inner not in MODULES and "." in inner:
            inner = inner.rpartition(".")[0]
        if inner in MODULES and inner != name:
            found.add(inner)
        elif inner == "" and dotted == "exobench":
            found.add("")
    return found


GRAPH = {name: imports(name) for name in MODULES}


def layer(name: str) -> int:
    return LAYERS[name.split(".")[0] if "." in name or name in LAYERS else ""]


def stage(name: str) -> int:
    """A group module's stage: its subpackage's place in STAGES (config rules last)."""
    parts = name.split(".")
    if parts[-1] in LAST:
        return len(STAGES)
    return STAGES.index(parts[1]) if len(parts) > 2 else 0


def test_the_import_graph_has_no_cycle():
    state: dict[str, int] = {}

    def visit(name: str, path: tuple[str, ...]) -> None:
        if state.get(name) == 2:
            return
        assert state.get(name) != 1, " -> ".join((*path, name))
        state[name] = 1
        for other in sorted(GRAPH[name]):
            visit(other, (*path, name))
        state[name] = 2

    for name in sorted(GRAPH):
        visit(name, ())


def test_no_module_imports_from_a_later_stage():
    late = []
    for name, imported in GRAPH.items():
        for other in imported:
            if layer(other) > layer(name):
                late.append(f"{name} imports {other} (a later layer)")
            group, other_group = name.split(".")[0], other.split(".")[0]
            if layer(name) == layer(other) == 2 and group != other_group:
                late.append(f"{name} imports {other} (another group)")
            elif layer(name) == 2 and group == other_group and stage(other) > stage(name):
                late.append(f"{name} imports {other} (a later stage of its group)")
    assert not late, "\n".join(sorted(late))


def script_group(script: Path) -> str:
    """The group a rule's script belongs to (its name's prefix)."""
    for prefix, group in VALIDATION_SCRIPTS.items():
        if script.stem.startswith(prefix):
            return group
    if script.stem in SHARED_SCRIPTS:
        return ""
    return script.stem.split("_")[0]


def test_the_package_root_holds_only_what_the_groups_share():
    # who imports what: the package's modules and every rule's script (as its group)
    importers = dict(GRAPH)
    for script in sorted(SCRIPTS.glob("*.py")):
        imported = {module_name(f) for f in codedeps.code_files(script)}
        importers[f"{script_group(script)}.<script {script.stem}>"] = imported
    assert {script_group(s) for s in SCRIPTS.glob("*.py")} - {"", "selection"} == set(GROUPS)
    for name in SHARED_SCRIPTS:
        imported = {module_name(f) for f in codedeps.code_files(SCRIPTS / f"{name}.py")}
        assert all(layer(m) == 0 for m in imported), (name, imported)

    def users(target: str, seen: frozenset = frozenset()) -> set[str]:
        """The groups that import ``target``, directly or through shared modules."""
        out = set()
        for name, imported in importers.items():
            if target in imported and name not in seen:
                if name.split(".")[0] in GROUPS:
                    out.add(name.split(".")[0])
                else:
                    out |= users(name, seen | {target})
        return out

    root = [name for name in MODULES if name and "." not in name and name not in LAYERS]
    assert {"tables", "figures", "studies", "errors"} <= set(root)
    single = {name: users(name) for name in root if len(users(name)) == 1}
    assert not single, single


@pytest.mark.parametrize("generator", GENERATORS)
def test_an_independent_generator_imports_nothing_from_exobench_but_itself(generator):
    own = [name for name in MODULES if name == generator or name.startswith(f"{generator}.")]
    assert len(own) > 1
    for name in own:
        outside = {other for other in GRAPH[name] if other not in own}
        assert not outside, f"{name} imports {sorted(outside)}"
        tree = ast.parse(MODULES[name].read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level:
                assert node.level == 1 or name == generator, f"{name}: relative import outside"
    # importing it runs its parent packages' __init__ files: they import nothing either
    parents = generator.split(".")
    for depth in range(1, len(parents)):
        parent = ".".join(parents[:depth])
        assert not GRAPH[parent], f"{parent} (a parent of {generator}) imports {GRAPH[parent]}"
