"""The study the paper runs on each scene, shared by `cases.slope` and `cases.belt`:

1. x(t) of the three laws with the automatic step size (Fig. 5 / Fig. 13);
2. each law at the automatic step size and RK4 with h = 1e-3 s and 1e-4 s (Figs. 6-8 / 14-16);
3. each law at three error tolerances (Figs. 9-11 / 17-19);
4. the CPU-time table (Table 2 / Table 3), with our counters beside the paper's seconds.

"Automatic" is DOPRI5 with h_min = 1e-6 s, h_max = 1e-2 s (the paper's range) and
rtol = 1e-6, atol = 1e-9 (AUTO_RTOL, ATOL_RATIO). The three tolerances default to
rtol = 1e-2, 1e-4, 1e-6 with atol = 1e-3 rtol: atol is in the state's units (m, m/s), and 1e-3
makes the test relative for any state component above 1 mm (or 1 mm/s): below the scenes'
displacements (0.1 m) and velocities (1.5 m/s), and below the smooth laws' creep speeds on the
slope (1.3 and 5.0 mm/s), so every tolerance acts on the motion that matters; rtol = 1e-2 is as
loose as an engineering code would go and 1e-6 is the automatic default. The tightest tolerance equals the automatic one, so that run is made
once and appears in both figures.
"""
from __future__ import annotations

import argparse
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from . import _common as c

LAWS: tuple[str, ...] = c.PAPER_LAWS
#: The paper's figure order within Figs. 6-8 and 9-11 (and 14-16, 17-19).
PAPER_LAW_ORDER: tuple[str, ...] = ("recurdyn", "proposed", "coulomb")
STEP_SIZES: tuple[float, ...] = (1e-3, 1e-4)      # RK4 fixed steps [s]
AUTO_RTOL: float = 1e-6                            # automatic mode's rtol [-]
TOLERANCES: tuple[float, ...] = (1e-2, 1e-4, 1e-6)  # rtol of Figs. 9-11 / 17-19 [-]
ATOL_RATIO: float = 1e-3                           # atol = ATOL_RATIO * rtol [m, m/s]
HMIN: float = 1e-6                                 # automatic range [s]
HMAX: float = 1e-2
MAX_STEPS: int = 10**8                             # the library's default step budget

Metrics = Callable[["c.Run", "c.Outcome", dict[str, float]], dict[str, float | None]]


@dataclass(frozen=True)
class SceneSpec:
    """What differs between the two scenes."""

    scene: str                        # "slope" or "belt"
    fig_auto: int                     # figure of the three laws, automatic step
    fig_steps: int                    # first of the three step-size figures
    fig_tol: int                      # first of the three tolerance figures
    table: int                        # CPU-time table number
    paper_cpu: dict[str, tuple[float, float, float]]  # law -> (auto, 1e-3, 1e-4) [s]
    metrics: Metrics                  # scene-specific columns of the table
    metric_columns: tuple[str, ...]   # their headers (with units)


def mode_label(run: c.Run) -> str:
    """'automatic', 'h=0.001' or 'rtol=0.0001' (the automatic run is the AUTO_RTOL one)."""
    if run.fixed_step:
        return f"h={run.h:g}"
    return f"rtol={run.rtol:g}"


def build_runs(spec: SceneSpec, *, t_end: float, n_out: int, params: dict[str, float],
               rtols: Sequence[float], auto_rtol: float = AUTO_RTOL,
               atol_ratio: float = ATOL_RATIO, max_steps: int | None = None) -> dict[str, Any]:
    """The runs each figure needs: {"auto": {law: Run}, "steps": {law: [Run]},
    "tol": {law: [Run]}}. Equal runs are equal objects, so they are simulated once."""
    frozen = tuple(sorted(params.items()))

    def dopri(law: str, rtol: float) -> c.Run:
        return c.Run(spec.scene, law, "dopri5", t_end, n_out, rtol=rtol,
                     atol=rtol * atol_ratio, hmin=HMIN, hmax=HMAX, params=frozen,
                     max_steps=max_steps)

    def rk4(law: str, h: float) -> c.Run:
        return c.Run(spec.scene, law, "rk4", t_end, n_out, h=h, params=frozen,
                     max_steps=max_steps)

    return {"auto": {law: dopri(law, auto_rtol) for law in LAWS},
            "steps": {law: [dopri(law, auto_rtol)] + [rk4(law, h) for h in STEP_SIZES]
                      for law in LAWS},
            "tol": {law: [dopri(law, r) for r in rtols] for law in LAWS}}


def all_runs(plan: dict[str, Any]) -> list[c.Run]:
    """Every run of a plan (with repetitions; run_all removes them)."""
    runs = list(plan["auto"].values())
    for key in ("steps", "tol"):
        for law_runs in plan[key].values():
            runs += law_runs
    return runs


def fig_name(number: int, scene: str, what: str) -> str:
    """File stem of a figure, e.g. fig06_slope_steps_recurdyn."""
    return f"fig{number:02d}_{scene}_{what}"


def write_figure_csvs(spec: SceneSpec, plan: dict[str, Any], out: dict[c.Run, c.Outcome],
                      outdir: Path) -> list[Path]:
    """The CSV of every figure: time [s] and one displacement column [m] per series."""
    t = out[plan["auto"][LAWS[0]]].t
    files = [c.write_columns(outdir / f"{fig_name(spec.fig_auto, spec.scene, 'automatic')}.csv",
                             {"t [s]": t, **{f"x {law} [m]": out[plan['auto'][law]].x
                                             for law in LAWS}})]
    for first, key, what in ((spec.fig_steps, "steps", "steps"), (spec.fig_tol, "tol", "tolerances")):
        for i, law in enumerate(PAPER_LAW_ORDER):
            cols = {"t [s]": t}
            for j, run in enumerate(plan[key][law]):
                label = "automatic" if (key == "steps" and j == 0) else mode_label(run)
                cols[f"x {label} [m]"] = out[run].x
            files.append(c.write_columns(outdir / f"{fig_name(first + i, spec.scene, f'{what}_{law}')}.csv",
                                         cols))
    return files


TABLE_HEADER: tuple[str, ...] = (
    "law [-]", "mode [-]", "method [-]", "h [s]", "rtol [-]", "atol [m]", "x_end [m]")
TABLE_TAIL: tuple[str, ...] = (
    "cpu_seconds [s]", "paper_cpu_seconds [s]", "cpu_ratio_to_h1e-3 [-]",
    "paper_ratio_to_h1e-3 [-]", "nfev_ratio_to_h1e-3 [-]", "nfev [-]", "nstep [-]",
    "nreject [-]", "nforced [-]", "wall_seconds [s]")


def table_rows(spec: SceneSpec, plan: dict[str, Any], out: dict[c.Run, c.Outcome],
               params: dict[str, float]) -> list[list[Any]]:
    """One row per distinct run of each law: the paper's three modes first (automatic, 1e-3,
    1e-4; these carry the paper's CPU time), then the other tolerances."""
    rows = []
    for law in PAPER_LAW_ORDER:
        steps = plan["steps"][law]
        extra = [r for r in plan["tol"][law] if r not in steps]
        ref = out[steps[1]]                                   # h = 1e-3
        for k, run in enumerate(steps + extra):
            o = out[run]
            paper = spec.paper_cpu[law][k] if k < 3 else None
            mode = "automatic" if k == 0 else mode_label(run)
            metrics = spec.metrics(run, o, params)
            rows.append([law, mode, run.method, run.h, run.rtol, run.atol, float(o.x[-1]),
                         *(metrics[col] for col in spec.metric_columns),
                         o.stats["cpu_seconds"], paper,
                         o.stats["cpu_seconds"] / max(ref.stats["cpu_seconds"], 1e-9),
                         None if paper is None else paper / spec.paper_cpu[law][1],
                         o.stats["nfev"] / ref.stats["nfev"],
                         o.stats["nfev"], o.stats["nstep"], o.stats["nreject"],
                         o.stats["nforced"], o.wall_seconds])
    return rows


def write_table(spec: SceneSpec, rows: list[list[Any]], outdir: Path) -> list[Path]:
    """Table CSV and its Markdown rendering."""
    header = list(TABLE_HEADER) + list(spec.metric_columns) + list(TABLE_TAIL)
    stem = f"table{spec.table}_{spec.scene}_cpu"
    csv_path = c.write_csv(outdir / f"{stem}.csv", header, rows)
    return [csv_path, c.write_text(outdir / f"{stem}.md", table_markdown(csv_path))]


def table_markdown(csv_path: Path) -> str:
    """Render a table CSV as Markdown (from the CSV alone)."""
    cols = c.read_csv(csv_path)
    names = list(cols)
    keep = [n for n in names if n not in ("method [-]", "h [s]", "rtol [-]", "atol [m]",
                                           "wall_seconds [s]", "nreject [-]")]
    n = len(cols[names[0]])

    def value(name: str, i: int) -> Any:
        text = cols[name][i]
        if text == "" or name in ("law [-]", "mode [-]"):
            return text
        v = float(text)
        return int(v) if v.is_integer() and abs(v) >= 1 else v

    return c.markdown_table(keep, ([value(k, i) for k in keep] for i in range(n)))


def plot_table(csv_path: Path, png_path: Path, note: str = "") -> Path:
    """Points (log axis) of the relative cost (to RK4 with h = 1e-3 of the same law) of the paper's
    three modes: the paper's CPU time, our CPU time and our function evaluations."""
    cols = c.read_csv(csv_path)
    rows = [i for i, p in enumerate(cols["paper_cpu_seconds [s]"]) if p != ""]
    def mode(text: str) -> str:
        if text == "automatic":
            return "DOPRI5 automatic"
        return f"RK4, h = {float(text[2:]):.0e} s".replace("e-0", "e-")

    labels = [f"{c.LAW_LABELS[cols['law [-]'][i]].split(' (')[0]}, {mode(cols['mode [-]'][i])}"
              for i in rows]
    series = (("paper_ratio_to_h1e-3 [-]", "paper's CPU time"),
              ("cpu_ratio_to_h1e-3 [-]", "our CPU time"),
              ("nfev_ratio_to_h1e-3 [-]", "our function evaluations"))
    fig, ax = c.new_figure(width=c.figure_width(1), height=4.0)
    y = np.arange(len(rows))
    # points, not bars, on the log axis (a bar's length from an arbitrary baseline means nothing)
    for k, (name, label) in enumerate(series):
        ax.semilogx([float(cols[name][i]) for i in rows], y + (k - 1) * 0.2, ("o", "s", "^")[k],
                    ms=5, label=label, color=c._style.SEQUENCE[k], linestyle="none")
    ax.axvline(1.0, color="k", linewidth=0.6, label="1: RK4, h = 1e-3 s of the law")
    ax.margins(x=0.1, y=0.06)             # no marker clipped at the frame
    ax.set_yticks(y, labels)
    ax.invert_yaxis()
    ax.set_xlabel("relative cost [-]")
    number, scene = csv_path.stem.split("_")[:2]
    fig.suptitle(f"Table {number[5:]}: {c._style.name(scene)}" + (f" ({note})" if note else ""))
    c.figure_legend(fig, [ax])
    return c.save_figure(fig, png_path)


def title_for(stem: str, note: str = "") -> str:
    """A plot title from a file stem such as fig06_slope_steps_recurdyn: the figure, the scene
    and the law (the runs shown and their parameters are in the legend); `note` names
    parameters that differ from the paper's."""
    parts = stem.split("_")
    number = int(parts[0][3:])
    scene = c._style.name(parts[1])
    tail = f" ({note})" if note else ""
    if parts[2] == "automatic":
        return f"Fig. {number}: {scene}, DOPRI5 automatic{tail}"
    law = c.LAW_LABELS[parts[3]].split(" (")[0]
    return f"Fig. {number}: {scene}, {law} law{tail}"


def plot(csv_path: str | Path, outdir: str | Path, note: str = "") -> Path:
    """Render one CSV of this study (a figure or the table) as PNG and PDF in outdir; `note`
    (parameters that differ from the paper's) goes into the title."""
    csv_path = Path(csv_path)
    png = Path(outdir) / f"{csv_path.stem}.png"
    if csv_path.stem.startswith("table"):
        return plot_table(csv_path, png, note)
    return c.plot_time_series(csv_path, png, title_for(csv_path.stem, note))


def run(spec: SceneSpec, outdir: str | Path, *, t_end: float, n_out: int,
        params: dict[str, float], rtols: Sequence[float] = TOLERANCES,
        auto_rtol: float = AUTO_RTOL, atol_ratio: float = ATOL_RATIO, workers: int = 2,
        quiet: bool = False, max_steps: int | None = None) -> list[Path]:
    """Simulate every distinct run of the study, write all CSVs and the table; returns the
    CSV and Markdown paths (PNGs come from `plot`)."""
    outdir = Path(outdir)
    plan = build_runs(spec, t_end=t_end, n_out=n_out, params=params, rtols=rtols,
                      auto_rtol=auto_rtol, atol_ratio=atol_ratio, max_steps=max_steps)
    out = c.run_all(all_runs(plan), workers=workers, quiet=quiet)
    files = write_figure_csvs(spec, plan, out, outdir)
    files += write_table(spec, table_rows(spec, plan, out, params), outdir)
    return files


def add_study_options(parser: argparse.ArgumentParser, *, t_end: float, n_out: int) -> None:
    """--t-end, --points and the tolerance options."""
    parser.add_argument("--t-end", type=c.positive_float, default=t_end,
                        help="simulated time [s] (default %(default)s)")
    parser.add_argument("--points", type=c.positive_int, default=n_out,
                        help="output points on [0, t_end] (default %(default)s)")
    parser.add_argument("--rtols", type=c.rtol_value, nargs=3, default=list(TOLERANCES),
                        metavar="RTOL", help="the three relative tolerances of the tolerance "
                        "figures [-], each in [100 eps = 2.2e-14, 1) (default 1e-2 1e-4 1e-6)")
    parser.add_argument("--atol-ratio", type=c.positive_float, default=ATOL_RATIO,
                        help="atol = ratio * rtol [m, m/s] (default %(default)s)")
    parser.add_argument("--max-steps", type=c.count, default=MAX_STEPS,
                        help="step budget of every run, >= 1 (default 10^8, the library's); "
                        "RK4's t_end/h steps must fit in it")


def check_inputs(scene: str, params: dict[str, float], *, t_end: float, n_out: int,
                 rtols: Sequence[float], atol_ratio: float) -> None:
    """Let the library validate every input before the study starts: one step of each law
    with the scene parameters, t_end, n_out and the tightest and loosest tolerance. Raises the
    library's ValueError (naming the parameter and its accepted range) for a bad value."""
    import stickslip
    for law in LAWS:
        for rtol in {min(*rtols, AUTO_RTOL), max(*rtols, AUTO_RTOL)}:
            try:
                stickslip.simulate(scene, law, method="dopri5", t_end=t_end, n_out=n_out,
                                   rtol=rtol, atol=rtol * atol_ratio, hmin=HMIN, hmax=HMAX,
                                   max_steps=1, ignore_unused=True, **params)
            except stickslip.IntegrationError:
                pass                          # the one-step budget ran out: inputs are fine


def main(spec: SceneSpec, argv: Sequence[str] | None, *, description: str, t_end: float,
         n_out: int, add_scene_options: Callable[[argparse.ArgumentParser], None],
         scene_params: Callable[[argparse.Namespace], dict[str, float]],
         run_scene: Callable[..., list[Path]]) -> list[Path]:
    """The command line of a scene driver: parse, run, plot, print where files went."""
    parser = argparse.ArgumentParser(prog=f"python -m cases.{spec.scene}", description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    c.add_common_options(parser)
    add_study_options(parser, t_end=t_end, n_out=n_out)
    add_scene_options(parser)
    c.add_law_options(parser)
    args = parser.parse_args(argv)
    params = {**c.checked_law_params(parser, args), **scene_params(args)}
    too_long = args.t_end / min(STEP_SIZES)
    if too_long > args.max_steps:
        parser.error(f"argument --t-end: must be <= {args.max_steps * min(STEP_SIZES):g} s with "
                     f"--max-steps {args.max_steps}: RK4 with h = {min(STEP_SIZES):g} s would need "
                     f"t_end/h = {too_long:.3g} steps, beyond the step budget")
    try:
        check_inputs(spec.scene, params, t_end=args.t_end, n_out=args.points, rtols=args.rtols,
                     atol_ratio=args.atol_ratio)
    except ValueError as exc:                 # a scene parameter the library rejects
        parser.error(str(exc))
    outdir, note = c.parameter_outdir(args.outdir, c.changed_options(parser, args))
    c.check_writable(parser, outdir)
    c.log(f"{spec.scene}: simulating ({args.workers} workers) -> {outdir}", args.quiet)
    try:
        files = run_scene(outdir, t_end=args.t_end, n_out=args.points, params=params,
                          rtols=args.rtols, atol_ratio=args.atol_ratio, workers=args.workers,
                          quiet=args.quiet, max_steps=args.max_steps)
    except c.SimulationFailed as exc:
        parser.exit(1, f"{parser.prog}: simulation failed: {exc}\n")
    except ValueError as exc:                 # a scene parameter the library rejects
        parser.error(str(exc))
    files += [plot(f, outdir, note) for f in files if f.suffix == ".csv"]
    return c.finish(parser.prog.split()[-1], argv, files)
