"""The package layering: every import inside ``dolfinx_seal`` points down the table.

An AST walk over the sources (module-level and function-level imports alike).
A unit is a top-level module (``params``) or a subpackage (``film``); a unit may
import itself and any unit of a lower layer, nothing of its own layer or above.
Strict layers exclude cycles between packages and upward imports (``film`` or
``solid`` importing ``scenes``, ``coupled`` importing ``scenes``).  The table is
drawn in the README's layout section.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "dolfinx_seal"

#: unit -> layer (imports go from a higher layer to a strictly lower one)
LAYERS: dict[str, int] = {
    "errors": 0,
    "params": 1, "mpi": 1, "compat": 1, "__init__": 1,
    "output": 2, "roughness": 2, "solvers": 2, "meshing": 2, "compiled": 2,
    "contact": 3, "friction": 3, "verification": 3, "meshcmd": 3, "checkpoint": 3,
    "surface": 4,
    "solid": 5, "film": 5,
    "coupled": 6,
    "scenes": 7,
    "studies": 8, "stability": 8,
    "paramdoc": 8,
    "cli": 9,
}  # fmt: skip


def _unit(path: Path) -> str:
    rel = path.relative_to(PACKAGE)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _imported_units(path: Path) -> list[tuple[str, int]]:
    """(unit, line) of every ``dolfinx_seal`` import in ``path``."""
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    here = list(rel.parts if path.name != "__init__.py" else rel.parts[:-1])
    found: list[tuple[str, int]] = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the importing package
                base = here[: len(here) - node.level + (path.name == "__init__.py")]
                module = ".".join([*base, *([node.module] if node.module else [])])
            else:
                module = node.module or ""
            # ``from dolfinx_seal import scenes`` imports the unit ``scenes``
            targets = (
                [f"{module}.{a.name}" for a in node.names] if module == "dolfinx_seal" else [module]
            )
        else:
            continue
        for t in targets:
            parts = t.split(".")
            if parts[0] == "dolfinx_seal" and len(parts) > 1:
                found.append((parts[1], node.lineno))
    return found


SOURCES = sorted(PACKAGE.rglob("*.py"))


def test_every_unit_has_a_layer():
    units = {_unit(p) for p in SOURCES}
    assert units <= set(LAYERS), f"add to LAYERS: {sorted(units - set(LAYERS))}"


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_point_down(path: Path):
    src = _unit(path)
    bad = [
        f"line {line}: {src} (layer {LAYERS[src]}) imports {dst} (layer {LAYERS.get(dst)})"
        for dst, line in _imported_units(path)
        if dst != src and (dst not in LAYERS or LAYERS[dst] >= LAYERS[src])
    ]
    assert not bad, f"{path.relative_to(PACKAGE)}: " + "; ".join(bad)


def test_the_walk_sees_function_level_and_package_imports(tmp_path):
    """The walker finds the import forms the check relies on (else it could pass vacuously)."""
    mod = PACKAGE / "studies.py"
    units = {u for u, _ in _imported_units(mod)}
    assert "scenes" in units  # ``from dolfinx_seal import scenes``
    cli = {u for u, _ in _imported_units(PACKAGE / "cli.py")}
    assert {"studies", "paramdoc"} <= cli  # imported inside functions
