"""Form compilation prints nothing unless it fails (``dolfinx_seal.compat.quiet_jit``).

The C compiler that CFFI runs writes to the process's file descriptors, not to
``sys.stderr``, so these tests capture at the descriptor level (``capfd``) and
compile fresh forms in an empty cache directory.  The plain forms of this stack
compile without warnings, so the tests add ``-Wextra`` (the generated kernels
then have unused parameters): without the quiet mechanism the compiler prints
warnings and the first test fails, as the second shows.
"""

from __future__ import annotations

import ast
import uuid
from pathlib import Path

import pytest

dolfinx = pytest.importorskip("dolfinx")

import ufl  # noqa: E402
from mpi4py import MPI  # noqa: E402

from dolfinx_seal import compat  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
WARNING_FLAGS = ["-O1", "-Wall", "-Wextra"]


def _fresh_form(cache: Path, extra_args: list[str]) -> None:
    mesh = dolfinx.mesh.create_unit_square(MPI.COMM_SELF, 2, 2)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    u = dolfinx.fem.Function(V)
    k = float(uuid.uuid4().int % 1000) + 0.5  # a form no cache has seen
    jit = {"cache_dir": str(cache), "cffi_extra_compile_args": list(extra_args)}
    dolfinx.fem.form((u * u + k) * ufl.dx + u * ufl.ds, jit_options=jit)


@pytest.mark.skip_in_parallel
def test_form_compilation_prints_no_compiler_warnings(tmp_path, capfd, monkeypatch):
    monkeypatch.delenv(compat.JIT_WARNINGS_ENV, raising=False)
    capfd.readouterr()
    _fresh_form(tmp_path / "cache", WARNING_FLAGS)
    out, err = capfd.readouterr()
    assert list((tmp_path / "cache").glob("libffcx_forms_*.so")), "nothing was compiled"
    assert "warning" not in (out + err) and "libffcx" not in (out + err), out + err
    assert out == "" and err == ""


@pytest.mark.skip_in_parallel
def test_the_warnings_exist_and_the_capture_sees_them(tmp_path, capfd, monkeypatch):
    """With the switch ``DOLFINX_SEAL_JIT_WARNINGS=1`` the same compilation is noisy."""
    monkeypatch.setenv(compat.JIT_WARNINGS_ENV, "1")
    capfd.readouterr()
    _fresh_form(tmp_path / "cache", WARNING_FLAGS)
    _, err = capfd.readouterr()
    assert "warning:" in err and "libffcx_forms_" in err


@pytest.mark.skip_in_parallel
def test_a_failing_compilation_still_raises_with_the_compiler_error(tmp_path, capfd, monkeypatch):
    monkeypatch.delenv(compat.JIT_WARNINGS_ENV, raising=False)
    capfd.readouterr()
    with pytest.raises(Exception, match=r"failed|rror"):
        _fresh_form(tmp_path / "cache", ["-include", "dolfinx_seal_no_such_header.h"])
    _, err = capfd.readouterr()
    assert "dolfinx_seal_no_such_header.h" in err and "error" in err


def test_quiet_options_survive_caller_options():
    opts = dolfinx.jit.get_options({"cffi_extra_compile_args": ["-O3"]})
    assert opts["cffi_extra_compile_args"] == ["-O3", "-w"]
    assert dolfinx.jit.get_options()["cffi_extra_compile_args"][-1] == "-w"
    compat.quiet_jit()  # idempotent
    assert dolfinx.jit.get_options({"cffi_extra_compile_args": []})["cffi_extra_compile_args"] == [
        "-w"
    ]


def _imports(path: Path) -> tuple[set[str], bool]:
    """Top-level imports of the project packages in ``path``, and whether it imports DOLFINx."""
    tree = ast.parse(path.read_text())
    mods, uses_dolfinx = set(), False
    for node in tree.body:
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        for n in names:
            if n.split(".")[0] == "dolfinx":
                uses_dolfinx = True
            if n.split(".")[0] in ("dolfinx_seal", "geometry"):
                mods.add(n)
    return mods, uses_dolfinx


def _module_file(name: str) -> Path | None:
    base = ROOT.joinpath(*name.split("."))
    for p in (base.with_suffix(".py"), base / "__init__.py"):
        if p.is_file():
            return p
    return None


def test_every_module_that_imports_dolfinx_loads_compat():
    """compat (and with it the quiet JIT) is imported before any module can compile a form."""
    files = sorted([*(ROOT / "dolfinx_seal").rglob("*.py"), *(ROOT / "geometry").rglob("*.py")])
    graph, users = {}, []
    for f in files:
        name = ".".join(f.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        graph[name], uses = _imports(f)
        if uses:
            users.append(name)
    assert "dolfinx_seal.solvers.snes" in users and "dolfinx_seal.film.surface" in users

    def closure(name: str) -> set[str]:
        seen, todo = set(), [name]
        while todo:
            m = todo.pop()
            for dep in graph.get(m, ()):
                # "from pkg import mod" names pkg.mod; a package import runs its __init__
                for cand in (dep, dep.rsplit(".", 1)[0]):
                    if cand not in seen and _module_file(cand) is not None:
                        seen.add(cand)
                        todo.append(cand)
                        parts = cand.split(".")
                        for i in range(1, len(parts)):
                            pkg = ".".join(parts[:i])
                            if pkg not in seen:
                                seen.add(pkg)
                                todo.append(pkg)
        return seen

    compat_ = "dolfinx_seal.compat"
    missing = [m for m in users if m != compat_ and compat_ not in closure(m)]
    assert not missing, f"import dolfinx_seal.compat in (or via) {missing}"
