"""Which exobench source files a job script runs: the rule's ``code`` param.

Snakemake reruns a job when one of its params differs from the value recorded with its outputs.
Giving every rule, as a param, the package modules its script imports (transitively, parsed with
:mod:`ast`, never imported) with the SHA-256 of their bytes makes an edit to ``src/exobench/``
rerun exactly the rules that run the edited code. The list is computed when the DAG is built,
so new modules are covered without editing any list. A param rather than input files: while
jobs wait, Snakemake's scheduler looks at every input file of every waiting job several times a
second (about 9 of its 28 CPU seconds in a default run, when each rule listed its 8 to 79
modules as inputs).
"""

from __future__ import annotations

import ast
import functools
import re
import textwrap
from pathlib import Path

from exobench.plumbing.provenance import PACKAGE_ROOT, code_sha256

PACKAGE = "exobench"
# one import statement on its own line(s): ``import a.b`` or ``from .a import (b, c)``
_IMPORT_LINE = re.compile(
    r"^[ \t]*(?:from[ \t]+[.\w]+[ \t]+import[ \t]+(?:\([^)]*\)|.*)|import[ \t]+.*)$", re.M
)


@functools.cache
def module_file(name: str, root: Path = PACKAGE_ROOT) -> Path | None:
    """Source file of the package module ``name`` (``exobench.a.b``), or None if none exists
    (looked up once per process: a DAG build asks for the same names hundreds of times)."""
    parts = name.split(".")
    if parts[0] != PACKAGE:
        return None
    base = root.joinpath(*parts[1:])
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _module_name(path: Path, root: Path) -> str:
    """Dotted module name of a package source file."""
    parts = path.relative_to(root).with_suffix("").parts
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join((PACKAGE, *parts))


def imported_names(path: Path, root: Path = PACKAGE_ROOT) -> set[str]:
    """Dotted names a source file may import: ``import a.b`` → a.b; ``from a import b`` → a, a.b.

    Relative imports are resolved against the file's package; imports inside functions count
    too (a lazy import still runs the module's code).
    """
    stat = Path(path).stat()
    return set(_names(Path(path).resolve(), root, (stat.st_mtime_ns, stat.st_size)))


@functools.cache
def _names(path: Path, root: Path, version: tuple[int, int]) -> frozenset[str]:
    """:func:`imported_names` of one version of a file (parsed once however many rules import
    it: a Snakefile's 47 code params share most modules)."""
    tree = _import_statements(path.read_text(encoding="utf-8"), str(path))
    here = _module_name(path, root) if path.is_relative_to(root) else ""
    is_package = path.name == "__init__.py"
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = here.split(".")
                anchor = anchor[: len(anchor) - node.level + (1 if is_package else 0)]
                base = ".".join([*anchor, node.module] if node.module else anchor)
            else:
                base = node.module or ""
            names.add(base)
            names.update(f"{base}.{alias.name}" for alias in node.names)
    return frozenset(names)


def _import_statements(text: str, filename: str) -> ast.Module:
    """The import statements of a source text as one parsed module: only the lines that start
    an import are parsed (ten times faster than the whole file, on every DAG build); the whole
    file when those lines do not parse on their own."""
    lines = [textwrap.dedent(match.group(0)).strip() for match in _IMPORT_LINE.finditer(text)]
    try:
        return ast.parse("\n".join(lines), filename=filename)
    except SyntaxError:
        return ast.parse(text, filename=filename)


def code_files(script: str | Path, root: Path = PACKAGE_ROOT) -> list[Path]:
    """Package source files a script runs: its exobench imports, theirs, and parent packages; a
    package that loads its modules by name (``importlib.import_module`` in a PEP 562
    ``__getattr__``) runs every one of them."""
    found: set[Path] = set()
    pending = [Path(script)]
    while pending:
        path = pending.pop()
        names = imported_names(path, root)
        if path.name == "__init__.py" and "importlib.import_module" in names:
            package = _module_name(path.resolve(), root)
            names = names | {f"{package}.{module.stem}" for module in path.parent.glob("*.py")}
        for name in names:
            parts = name.split(".")
            for depth in range(1, len(parts) + 1):
                source = module_file(".".join(parts[:depth]), root)
                if source is not None and source not in found:
                    found.add(source)
                    pending.append(source)
    return sorted(found)


def code_param(script: str | Path, root: Path = PACKAGE_ROOT) -> dict[str, object]:
    """A rule's ``code`` param: the package files its script runs (:func:`code_files`, named
    from the package's parent, ``exobench/…``, as a job finds them) and their
    :func:`provenance.code_sha256` (which names them from the package, ``…``)."""
    files = code_files(script, root)
    return {"files": [f.relative_to(root.parent).as_posix() for f in files],
            "sha256": code_sha256(files, root, read=_source)}  # fmt: skip


def _source(path: Path) -> bytes:
    """A source file's bytes, read once per version however many rules run it."""
    stat = path.stat()
    return _version_bytes(path, (stat.st_mtime_ns, stat.st_size))


@functools.cache
def _version_bytes(path: Path, version: tuple[int, int]) -> bytes:
    """The bytes of one version (mtime, size) of a source file."""
    return path.read_bytes()
