"""Command line interface: ``dolfinx-seal``.

Sub-commands:

* ``versions``           -- DOLFINx, PETSc, petsc4py, mpi4py, gmsh, ... versions.
* ``scenes``             -- the registered scenes and what they compute.
* ``params SCENE``       -- every parameter of a scene: dotted name, default, unit,
  allowed values, meaning (``--all --markdown --output docs/parameters.md``
  regenerates the parameter reference).
* ``run SCENE``          -- one point of a scene (``--scene FILE.toml``, ``--set key=value``);
  prints the results-contract scalars with units, the full record is ``results.json``.
* ``sweep SCENE``        -- a sweep of one parameter (``--over NAME --values SPEC``);
  one line per finished point.  ``--chains K`` (under ``mpirun -n N``, K <= N) runs K
  independent chains of the values at once, each on N/K ranks.  ``--point-files K``
  writes the per-point folders (film maps, profiles) of every K-th point only.
* ``study SCENE``        -- error against run time over resolution levels.
* ``study stability SCENE`` -- the scene's stiff and extreme cases from its table
  (``studies/stability/SCENE.toml``): ``stability.csv``, ``.md``, ``.png``.
* ``mesh KIND``          -- build and save a mesh (``.msh``, ``info.json``, PNG).
* ``psd FILE``           -- PSD (``psd.csv``, ``psd.png``) and moments of a measured height map.

``run`` and ``sweep`` appear once scenes are registered.  Exit status: 0 done,
2 a bad input (``ParameterError``, before anything is assembled), 3 a solver
failure (``SolverError``; a sweep that did not finish every point, whose finished
points are in ``sweep.csv``), each with one line on stderr and no traceback.  They refuse an ``--out``
folder holding another scene's or other parameters' results (the same run again
overwrites); ``--force`` writes anyway.  ``sweep --resume`` goes on with the sweep
in ``--out`` (a killed or failed one, same scene, parameters and values): its rows
are kept and the points not finished are solved.  Unknown arguments
starting with ``-`` that follow ``--petsc`` are passed to PETSc's options
database (e.g. ``--petsc -snes_monitor``).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from dolfinx_seal import scenes as _scenes
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import print0, setup_logging, world
from dolfinx_seal.output import Progress, on_sweep_row, results_table, sweep_point_line, versions


def _cmd_versions(args: argparse.Namespace) -> int:
    v = versions()
    width = max(len(k) for k in v)
    for k, val in v.items():
        print0(f"{k:<{width}}  {val}")
    return 0


def _cmd_scenes(args: argparse.Namespace) -> int:
    for name in _scenes.available():
        print0(f"{name:<16} {_scenes.get(name).summary}")
    return 0


def _cmd_params(args: argparse.Namespace) -> int:
    from dolfinx_seal import paramdoc

    if args.all == (args.scene is not None):
        raise ParameterError("params: give one SCENE or --all")
    if args.all and (args.set or args.scene_file):
        raise ParameterError("params --all lists the defaults; --set/--scene-file need one SCENE")
    names = _scenes.available() if args.all else [args.scene]
    if args.markdown and args.all:
        text = paramdoc.markdown(names)
    else:
        chunks = []
        for name in names:
            rows = paramdoc.scene_parameters(name, args.scene_file, args.set)
            if args.markdown:
                chunks.append(f"## `{name}`\n\n{paramdoc.markdown_table(rows)}\n")
            else:
                given = bool(args.set or args.scene_file)
                table = paramdoc.text_table(rows, "value" if given else "default")
                note = (
                    "bounds that depend on other parameters are evaluated at these values; "
                    "units SI, - dimensionless"
                )
                chunks.append(f"{name}: {_scenes.get(name).summary}\n{table}\n({note})\n")
        text = "\n".join(chunks)
    if args.output:
        if world().rank == 0:
            Path(args.output).write_text(text if text.endswith("\n") else text + "\n")
        print0(f"written {args.output}")
    else:
        print0(text.rstrip("\n"))
    return 0


def _cmd_run(args: argparse.Namespace) -> int:
    p = _scenes.make_parameters(args.scene, args.scene_file, args.set)
    out = args.out or f"results/{args.scene}"
    with Progress(1, what=args.scene, verbose=args.verbose, leave=False):  # sub-steps only
        res = _scenes.run_scene(args.scene, p, out, force=args.force)
    print0(f"{args.scene} results:")
    print0(results_table(res, "results.json"))
    print0(f"results written to {out}/results.json")
    return 0 if res.get("converged", True) else 1


def _cmd_sweep(args: argparse.Namespace) -> int:
    from dolfinx_seal.paramdoc import field_unit

    p = _scenes.make_parameters(args.scene, args.scene_file, args.set)
    out = args.out or f"results/{args.scene}-sweep"
    values = _scenes.parse_values(args.values)
    unit = field_unit(p, args.over)
    if args.resume and args.force:
        raise ParameterError("--resume and --force: resume the sweep in --out, or overwrite it")
    if args.chains != 1:
        rows = _scenes.sweep_chains(
            args.scene, p, out, args.over, values, args.chains, force=args.force,
            resume=args.resume, unit=unit, point_files=args.point_files,
        )  # fmt: skip
        return _sweep_status(rows, values, out, args.over)
    progress = Progress(len(values), args.over, unit, verbose=args.verbose)

    def echo(row: dict) -> None:  # before progress.point counts the row
        n = progress.done + 1
        progress.write(f"[{n}/{len(values)}] {sweep_point_line(row, args.over, unit)}")

    with progress, on_sweep_row(Path(out) / "sweep.csv", echo):
        rows = _scenes.sweep_scene(
            args.scene, p, out, args.over, values, force=args.force, progress=progress,
            resume=args.resume, point_files=args.point_files,
        )  # fmt: skip
    return _sweep_status(rows, values, out, args.over)


def _sweep_status(rows: list[dict], values: list[float], out: str, over: str) -> int:
    """Exit status 0 when every point of a sweep finished; else the SolverError
    naming the points not finished and the first failure."""
    print0(f"{len(rows)} of {len(values)} points finished; {out}/sweep.csv, {out}/results.json")
    if len(rows) == len(values):
        return 0
    done = {float(r[over]) for r in rows if over in r}
    missing = [v for v in values if float(v) not in done]
    reasons = _sweep_failures(Path(out), over)
    why = f"; first failure: {reasons[0]}" if reasons else ""
    raise SolverError(
        f"sweep incomplete: {len(missing)} of {len(values)} points not finished ({over} = "
        f"{', '.join(f'{v:g}' for v in missing)}){why}; the {len(rows)} finished points are in "
        f"{out}/sweep.csv"
    )


def _sweep_failures(out: Path, over: str) -> list[str]:
    """What stopped the points of a sweep, from ``results.json`` (points whose solve
    raised) and ``sweep_failures.csv`` (continuation targets not reached)."""
    import csv
    import json

    reasons: list[str] = []
    try:
        summary = json.loads((out / "results.json").read_text())
        for f in summary.get("failed_points", []):
            at = f"{over} = {f[over]:g}: " if isinstance(f.get(over), int | float) else ""
            reasons.append(at + str(f.get("error", "")))
    except (OSError, ValueError):
        pass
    try:
        with (out / "sweep_failures.csv").open(newline="") as fh:
            for row in csv.DictReader(fh):
                reasons.append(f"film.speed = {float(row['speed']):g}: {row['error']}")
    except (OSError, ValueError, KeyError):
        pass
    return reasons


def _cmd_study(args: argparse.Namespace) -> int:
    from dolfinx_seal.studies import convergence_study

    if args.scene == "stability":
        return _cmd_stability(args)
    if args.target is not None:
        raise ParameterError(
            f"study {args.scene} {args.target}: one SCENE (or: study stability SCENE)"
        )
    if args.values is None:
        raise ParameterError("study SCENE: --values (the resolution levels) is required")
    p = _scenes.make_parameters(args.scene, args.scene_file, args.set)
    out = args.out or f"results/{args.scene}-study"
    values = _scenes.parse_values(args.values)
    with Progress(len(values), args.over, what="level", growth=True, verbose=args.verbose) as pr:
        rows = convergence_study(
            args.scene, p, out, args.over, values, args.quantities.split(","), args.reference, pr
        )
    for r in rows:
        print0(
            ", ".join(f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}" for k, v in r.items())
        )
    print0(f"{out}/study.csv, {out}/error_vs_time.png, {out}/results.json")
    return 0


def _cmd_stability(args: argparse.Namespace) -> int:
    """``study stability SCENE``: the scene's table of stiff and extreme cases."""
    from dolfinx_seal import stability

    if args.target not in _scenes.available():
        raise ParameterError(
            f"study stability: SCENE = {args.target!r} is not one of {_scenes.available()}"
        )
    if args.set or args.scene_file or args.values is not None:
        raise ParameterError(
            "study stability: the cases come from the table (--table); --set, --scene-file "
            "and --values are not used"
        )
    table = stability.read_table(args.table or stability.table_path(args.target))
    if table.scene != args.target:
        raise ParameterError(f"{table.path}: scene = {table.scene!r}, not {args.target!r}")
    out = args.out or f"results/stability/{args.target}"
    names = [c for c in args.cases.split(",") if c] if args.cases else None
    n = len(table.select(names))
    if args.report_only:
        if names:
            raise ParameterError("study stability --report-only: the cases are those in --out")
        rows = stability.rewrite_report(table, out)
    else:
        with Progress(n, "case", what="case", verbose=args.verbose) as pr:
            rows = stability.stability_study(table, out, names, pr)
    counts = {s: sum(r["status"] == s for r in rows) for s in stability.STATUSES}
    print0(", ".join(f"{k}: {v}" for k, v in counts.items()))
    print0(f"{out}/stability.csv, {out}/stability.md, {out}/stability.png")
    return 0 if counts["nan"] == 0 else 3


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (exposed for tests and documentation)."""
    parser = argparse.ArgumentParser(prog="dolfinx-seal", description=__doc__.splitlines()[0])
    parser.add_argument(
        "-v", "--verbose", action="store_true",
        help="debug logging: one line per Newton step, and every sub-step of the progress",
    )  # fmt: skip
    sub = parser.add_subparsers(dest="command", required=True)

    sp = sub.add_parser("versions", help="print the versions of the stack")
    sp.set_defaults(func=_cmd_versions)

    if _scenes.available():
        sp = sub.add_parser("scenes", help="list the scenes")
        sp.set_defaults(func=_cmd_scenes)

        def common(sp: argparse.ArgumentParser) -> None:
            sp.add_argument("scene", choices=_scenes.available())
            sp.add_argument(
                "--scene-file", help="TOML scene file ([parameters] table or flat keys)"
            )
            sp.add_argument(
                "--set", action="append", default=[], metavar="KEY=VALUE",
                help="override a parameter (dotted keys for nested ones); repeatable",
            )  # fmt: skip
            sp.add_argument("--out", help="output folder (default results/SCENE[-sweep])")

        sp = sub.add_parser(
            "params", help="list a scene's parameters: default, unit, allowed values, meaning"
        )
        sp.add_argument("scene", nargs="?", choices=_scenes.available())
        sp.add_argument("--all", action="store_true", help="every registered scene")
        sp.add_argument("--markdown", action="store_true", help="Markdown tables")
        sp.add_argument("--output", help="write to this file instead of the terminal")
        sp.add_argument("--scene-file", help="show the values resolved from this TOML file")
        sp.add_argument(
            "--set", action="append", default=[], metavar="KEY=VALUE",
            help="show the values (and dependent bounds) with this override; repeatable",
        )  # fmt: skip
        sp.set_defaults(func=_cmd_params)

        def force(sp: argparse.ArgumentParser) -> None:
            sp.add_argument(
                "--force", action="store_true",
                help="write into --out even if it holds another scene's or other parameters' "
                "results (refused otherwise)",
            )  # fmt: skip

        sp = sub.add_parser("run", help="run one point of a scene")
        common(sp)
        force(sp)
        sp.set_defaults(func=_cmd_run)

        sp = sub.add_parser("sweep", help="sweep one parameter of a scene")
        common(sp)
        force(sp)
        sp.add_argument("--over", required=True, help="parameter to sweep (e.g. speed)")
        sp.add_argument(
            "--values", required=True,
            help="comma-separated values, or start:stop:n[:log]",
        )  # fmt: skip
        sp.add_argument(
            "--resume", action="store_true",
            help="go on with the killed or failed sweep in --out (same scene, parameters and "
            "values): keep its rows, solve the points not finished",
        )  # fmt: skip
        sp.add_argument(
            "--chains", type=int, default=1, metavar="K",
            help="run K chains of the values at once (every K-th value of the walk order, "
            "each chain with its own start, on its share of the mpirun ranks; results "
            "per chain in OUT/chain-k, merged in OUT)",
        )  # fmt: skip
        sp.add_argument(
            "--point-files", type=int, default=1, metavar="K",
            help="write the own files of the first point, of every K-th after it and of "
            "the last value (OUT/speed_<U>/ or oil_pressure_<p>/: film maps, profiles; "
            "about 1 s a point for a 3D film map); 0: none; default 1: every point. "
            "sweep.csv, sweep.png and results.json are always written",
        )  # fmt: skip
        sp.set_defaults(func=_cmd_sweep)

        sp = sub.add_parser(
            "study", help="error against run time over discretisation levels (study SCENE), "
            "or the stiff and extreme cases of a scene (study stability SCENE)",
        )  # fmt: skip
        sp.add_argument("scene", choices=[*_scenes.available(), "stability"])
        sp.add_argument("target", nargs="?", help="study stability: the scene")
        sp.add_argument("--scene-file", help="TOML scene file ([parameters] table or flat keys)")
        sp.add_argument(
            "--set", action="append", default=[], metavar="KEY=VALUE",
            help="override a parameter (dotted keys for nested ones); repeatable",
        )  # fmt: skip
        sp.add_argument(
            "--out", help="output folder (default results/SCENE-study, results/stability/SCENE)"
        )
        sp.add_argument("--over", default="h_contact", help="resolution parameter (coarse to fine)")
        sp.add_argument("--values", help="levels, comma-separated or start:stop:n[:log]")
        sp.add_argument(
            "--table", help="study stability: the case table (default studies/stability/SCENE.toml)"
        )
        sp.add_argument(
            "--cases", help="study stability: comma-separated case names (default: all)"
        )
        sp.add_argument(
            "--report-only", action="store_true",
            help="study stability: rewrite the report of the run in --out (no solving)",
        )  # fmt: skip
        sp.add_argument(
            "--quantities", default="max_contact_pressure,contact_half_width",
            help="comma-separated result keys to follow",
        )  # fmt: skip
        sp.add_argument("--reference", default="hertz", choices=("hertz", "finest"))
        sp.set_defaults(func=_cmd_study)

    sp = sub.add_parser("psd", help="PSD and moments of a measured height map")
    sp.add_argument("file", help="height map: text rows of heights [m] or .npy")
    sp.add_argument("--pixel-size", type=float, default=None, help="[m] (or a text header)")
    sp.add_argument("--window", default="hann", choices=("hann", "none"))
    sp.add_argument("--out", default="results/psd", help="output folder")
    sp.set_defaults(func=_cmd_psd)

    from dolfinx_seal import meshcmd

    meshcmd.add_parser(sub)
    return parser


def _cmd_psd(args: argparse.Namespace) -> int:
    """``psd.csv`` (reusable as ``roughness.psd_file``), ``psd.png`` and the moments."""
    from dolfinx_seal.roughness.topography import topography_report

    out = Path(args.out)
    if world().rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    m = topography_report(args.file, args.pixel_size, out, window=args.window)
    for k, v in m.items():
        if isinstance(v, int | float):
            print0(f"  {k:22s} {v:.6g}")
    print0(f"wrote {out}/psd.csv and psd.png")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``dolfinx-seal``."""
    argv = list(sys.argv[1:] if argv is None else argv)
    petsc_args: list[str] = []
    if "--petsc" in argv:
        i = argv.index("--petsc")
        argv, petsc_args = argv[:i], argv[i + 1 :]
    if petsc_args:
        from petsc4py import PETSc

        opts = PETSc.Options()
        key = None
        for a in petsc_args:
            if a.startswith("-"):
                if key is not None:
                    opts[key] = ""
                key = a.lstrip("-")
            elif key is not None:
                opts[key] = a
                key = None
        if key is not None:
            opts[key] = ""
    args = build_parser().parse_args(argv)
    setup_logging("DEBUG" if args.verbose else "INFO")
    try:
        return int(args.func(args))
    except ParameterError as e:  # one line: the message may quote a file's line
        print(f"dolfinx-seal: parameter error: {' '.join(str(e).split())}", file=sys.stderr)
        return 2
    except SolverError as e:
        print(f"dolfinx-seal: solver error: {' '.join(str(e).split())}", file=sys.stderr)
        return 3


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
