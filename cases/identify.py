"""Which friction law describes a measured contact? Fit every candidate law to measured
force-displacement records (stickslip.fit_friction), rank them by BIC on the fitted records and
by the error on held-out records, and write the parameters with their intervals, the scores,
figures and a Markdown report::

    python -m cases.identify --outdir out/                      # the damper data, every law
    python -m cases.identify --data a.csv.gz b.csv.gz --laws dahl lugre

Data. By default the 20 friction-damper records of data/friction-damper/ (CC BY-SA 4.0, see
its README). Records are grouped by band tension (the tension sets the unmeasured normal force
and the asymmetry differs between tensions): each group gets its own fit of each law, in force
levels [N] (the normal force is not measured). Each record is subsampled to SAMPLES_PER_CYCLE
(48) samples per cycle of its sine (every 21st sample at 0.25 Hz, every 3rd at 2 Hz), so that
every test weighs the same per cycle and a full run costs about 35 s of CPU.

Choice. The law to use is the simplest that explains the held-out records: the fewest fitted
parameters among the laws whose held-out error is within TIE (5 %, relative) of the best.

Split. Within a group, the records form a grid of frequency x amplitude; a record is fitted
when (frequency index + amplitude index) is even and held out otherwise (a checkerboard): each
frequency and each amplitude appears on both sides, so the held-out error measures how a law
carries over to a new combination of speed and stroke, not to speeds it has never seen.
Records without that metadata alternate (even positions fitted).

Every law is fitted with backlash and asymmetry (options of stickslip.prescribed_motion) fitted
too (the static laws from the backlash starts fit_friction picks from a scan of widths); the thresholds at
which Coulomb's and Karnopp's laws jump (v_s, dv) are fixed at
JUMP_VELOCITY (a gradient method cannot move a jump), GMS's element count at its default and
its attraction constant at GMS_C (it barely changes the force on sines).
"""
from __future__ import annotations

import argparse
import multiprocessing
import time
import warnings
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness import style as _style

from . import _common as c
SAMPLES_PER_CYCLE: int = 48
JUMP_VELOCITY: float = 1e-3        # [m/s]
GMS_C: float = 1e6                 # [N/s]
RTOL: float = 1e-4                 # state integration of the fits (force error ~ 1e-4 of its level)
DIFF_STEP: float = 1e-2            # finite-difference step, well above RTOL
TIE: float = 0.05                  # held-out errors within 5 % of the best count as equal
STATIC_REFERENCE: str = "stribeck"  # the static (velocity-only) law the report sets beside the chosen one
#: Display names of the laws (harness.style's, one set for every figure).
LAW_NAMES: dict[str, str] = _style.LAW_NAMES
#: Colour of the measured force (a model's is its law's: harness.style.LAW_COLORS).
MEASURED_COLOR: str = "0.6"
#: Colours of the load groups in the score figure (not laws or methods: the cycle's).
GROUP_COLORS: tuple[str, ...] = _style.VARIANT_COLORS[1:]
PNG_DPI: int = 200


def fixed_for(law: str) -> dict[str, float]:
    """The parameters this study holds fixed for `law` (module notes)."""
    return {"coulomb": {"v_s": JUMP_VELOCITY}, "karnopp": {"dv": JUMP_VELOCITY},
            "gms": {"gms_c": GMS_C}}.get(law, {})


def load_groups(files: Sequence[Path]) -> dict[str, list[tuple[Any, bool]]]:
    """Records grouped by tension ("36lb", or "all" without metadata), each with its split
    (True = fitted, False = held out), subsampled to SAMPLES_PER_CYCLE per cycle."""
    import stickslip
    recs = [stickslip.load_damper_record(f) for f in files]
    groups: dict[str, list[Any]] = {}
    for r in recs:
        groups.setdefault(f"{r.tension:g}lb" if r.tension is not None else "all", []).append(r)
    out: dict[str, list[tuple[Any, bool]]] = {}
    for key, members in groups.items():
        if all(r.frequency is not None and r.amplitude is not None for r in members):
            fs = sorted({r.frequency for r in members})
            amps = sorted({r.amplitude for r in members})
            split = [(fs.index(r.frequency) + amps.index(r.amplitude)) % 2 == 0 for r in members]
        else:
            split = [i % 2 == 0 for i in range(len(members))]
        if not any(split):
            split[0] = True
        sub = []
        for r, train in zip(members, split):
            dt = float(np.median(np.diff(r.t)))
            step = max(1, int(round(1.0 / (r.frequency * dt * SAMPLES_PER_CYCLE)))) if r.frequency else 1
            sub.append((r.subsample(step), train))
        out[key] = sub
    return out


def fit_one(job: tuple[str, str, list[Any], list[Any]]) -> dict[str, Any]:
    """Fit `law` on the group's fitted records, score it on the held-out ones (a worker)."""
    import stickslip
    group, law, train, held = job
    t0 = time.perf_counter()
    # a static law can only imitate the lag after a reversal by a wide backlash, and the cost
    # is far from convex in it: fit_friction starts such laws from the lowest widths of a scan
    # (identify.BACKLASH_GRID) too
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = stickslip.fit_friction(law, train, fixed=fixed_for(law), backlash="fit", asymmetry="fit",
                                     n_starts=1, rtol=RTOL, diff_step=DIFF_STEP)
    seconds = time.perf_counter() - t0
    held_score = fit.score(held) if held else None
    per_record = [(r.name, "fitted", fit.score(r)) for r in train] + [(r.name, "held out", fit.score(r)) for r in held]
    predictions = {r.name: fit.predict(r) for r in held}
    return {"group": group, "law": law, "fit": fit, "seconds": seconds, "held": held_score,
            "per_record": per_record, "predictions": predictions}


def run(outdir: str | Path, *, files: Sequence[Path] | None = None, laws: Sequence[str] | None = None,
        workers: int = 2, quiet: bool = False) -> list[Path]:
    """Fit, score and write the CSV files and the report; returns the files written."""
    import stickslip
    from ._progress import bar
    outdir = Path(outdir)
    files = list(files) if files else stickslip.damper_files()
    laws = list(laws) if laws else list(stickslip.LAWS)
    groups = load_groups(files)
    jobs = [(g, law, [r for r, tr in recs if tr], [r for r, tr in recs if not tr])
            for g, recs in groups.items() for law in laws]
    # the costliest (laws with states) first
    jobs.sort(key=lambda j: -stickslip.REGISTRY["law"][j[1]]["n_states"])
    results: list[dict[str, Any]] = []
    with bar(len(jobs), "  fits", quiet, unit="fit") as shown:
        if workers > 1:
            ctx = multiprocessing.get_context("fork" if "fork" in multiprocessing.get_all_start_methods() else None)
            with ctx.Pool(min(workers, len(jobs))) as pool:
                for res in pool.imap_unordered(fit_one, jobs):
                    results.append(res)
                    shown.update(note=f"{res['group']} {res['law']}: {res['seconds']:.1f} s")
        else:
            for job in jobs:
                results.append(fit_one(job))
                shown.update(note=f"{job[0]} {job[1]}: {results[-1]['seconds']:.1f} s")
    order = {law: i for i, law in enumerate(laws)}
    results.sort(key=lambda r: (r["group"], order[r["law"]]))
    files_out = write_outputs(outdir, groups, results)
    return files_out + write_correlations(outdir, results, outdir / "identify_scores.csv")


def write_outputs(outdir: Path, groups: dict[str, list[tuple[Any, bool]]],
                  results: list[dict[str, Any]]) -> list[Path]:
    """The CSV files (parameters, scores, per-record errors, held-out predictions) and the report."""
    files: list[Path] = []
    rows = []
    for r in results:
        fit = r["fit"]
        for name, value in fit.params.items():
            lo, hi = fit.ci95.get(name, (None, None))
            rows.append([r["group"], r["law"], name, value, fit.units[name],
                         fit.stderr.get(name), lo, hi, int(name in fit.free), int(name in fit.at_bound)])
    files.append(c.write_csv(outdir / "identify_params.csv",
                             ["group [-]", "law [-]", "parameter [-]", "value [unit]", "unit [-]",
                              "stderr [unit]", "ci95 low [unit]", "ci95 high [unit]", "fitted [-]",
                              "at bound [-]"], rows))
    rows = []
    for g in sorted({r["group"] for r in results}):
        best = min(r["fit"].bic for r in results if r["group"] == g)
        for r in (r for r in results if r["group"] == g):
            fit, held = r["fit"], r["held"]
            rows.append([g, r["law"], len(fit.free), fit.n_records, fit.n_samples, fit.rmse, fit.nrmse,
                         fit.aic, fit.bic, fit.bic - best, held["n_samples"] if held else None,
                         held["rmse"] if held else None, held["nrmse"] if held else None, r["seconds"]])
    files.append(c.write_csv(outdir / "identify_scores.csv",
                             ["group [-]", "law [-]", "fitted parameters [-]", "fitted records [-]",
                              "fitted samples [-]", "rmse fitted [N]", "nrmse fitted [-]", "AIC [-]",
                              "BIC [-]", "delta BIC [-]", "held-out samples [-]", "rmse held out [N]",
                              "nrmse held out [-]", "fit time [s]"], rows))
    rows = [[r["group"], r["law"], name, split, s["rmse"], s["nrmse"]]
            for r in results for name, split, s in r["per_record"]]
    files.append(c.write_csv(outdir / "identify_records.csv",
                             ["group [-]", "law [-]", "record [-]", "split [-]", "rmse [N]", "nrmse [-]"], rows))
    for g, recs in groups.items():
        held = [rec for rec, tr in recs if not tr]
        laws = [r["law"] for r in results if r["group"] == g]
        rows = []
        for rec in held:
            preds = [next(r for r in results if r["group"] == g and r["law"] == law)["predictions"][rec.name]
                     for law in laws]
            rows += [[rec.name, ti, xi, fi, *(p[i] for p in preds)]
                     for i, (ti, xi, fi) in enumerate(zip(rec.t, rec.x, rec.force))]
        if rows:
            files.append(c.write_csv(outdir / f"identify_predictions_{g}.csv",
                                     ["record [-]", "t [s]", "x [m]", "F measured [N]",
                                      *(f"F {law} [N]" for law in laws)], rows))
    return files


# --------------------------------------------------------------------------------------------
# Figures and report (from the CSV files alone)
# --------------------------------------------------------------------------------------------
def _rows(path: Path) -> list[dict[str, str]]:
    cols = c.read_csv(path)
    names = list(cols)
    return [dict(zip(names, vals)) for vals in zip(*cols.values())]


def choose(scores: list[dict[str, str]], group: str) -> tuple[str, list[dict[str, str]]]:
    """The law to use for `group` and the group's rows ranked by held-out error (by BIC without
    a held-out set). The simplest law that explains the data: among the laws whose held-out
    error is within TIE (relative) of the best, the one with the fewest fitted parameters."""
    mine = [r for r in scores if r["group [-]"] == group]
    has_held = all(r["nrmse held out [-]"] for r in mine)
    if not has_held:
        ranked = sorted(mine, key=lambda r: float(r["BIC [-]"]))
        return ranked[0]["law [-]"], ranked
    ranked = sorted(mine, key=lambda r: float(r["nrmse held out [-]"]))
    best = float(ranked[0]["nrmse held out [-]"])
    tied = [r for r in ranked if float(r["nrmse held out [-]"]) <= (1.0 + TIE) * best]
    return min(tied, key=lambda r: int(r["fitted parameters [-]"]))["law [-]"], ranked


def _save(fig: Any, path: Path) -> list[Path]:
    """PNG at PNG_DPI and a PDF copy, each written whole."""
    import matplotlib.pyplot as plt
    fig.tight_layout()
    try:
        png = c.atomic_write(path.with_suffix(".png"), lambda f: fig.savefig(f, format="png", dpi=PNG_DPI), binary=True)
        pdf = c.atomic_write(path.with_suffix(".pdf"), lambda f: fig.savefig(f, format="pdf"), binary=True)
    finally:
        plt.close(fig)
    return [png, pdf]


def shown_laws(chosen: str, available: Sequence[str]) -> list[str]:
    """The laws a figure compares: the chosen one, the static reference and Dahl."""
    out = [chosen]
    for law in (STATIC_REFERENCE, "dahl"):
        if law in available and law not in out:
            out.append(law)
    return out[:3]


#: Widths of the figures [in] (loops, residuals, correlations, scores); their fonts are scaled to
#: stay legible at a column width (harness.style.apply).
LOOPS_WIDTH: float = 4.6
RESIDUALS_WIDTH: float = 5.0
CORRELATION_WIDTH: float = 4.6
SCORES_WIDTH: float = 4.0


def plot(outdir: str | Path) -> list[Path]:
    """Loops and residuals of the held-out records, correlations of the chosen law's
    parameters, and the scores of every law."""
    import matplotlib.pyplot as plt
    outdir = Path(outdir)
    scores = _rows(outdir / "identify_scores.csv")
    groups = sorted({r["group [-]"] for r in scores})
    files: list[Path] = []
    for g in groups:
        chosen, _ = choose(scores, g)
        pred_path = outdir / f"identify_predictions_{g}.csv"
        if pred_path.exists():
            pr = c.read_csv(pred_path)
            names = list(dict.fromkeys(pr["record [-]"]))
            avail = [k.split()[1] for k in pr if k.startswith("F ") and k != "F measured [N]"]
            laws = shown_laws(chosen, avail)
            col = {k: np.array(v, dtype=float) for k, v in pr.items() if k != "record [-]"}
            which = np.array(pr["record [-]"])
            # a row per record, a column per law: a column of the page holds it at its fonts
            width = LOOPS_WIDTH
            _style.apply(width)
            fig, axes = plt.subplots(len(names), len(laws), figsize=(width, 1.2 + 1.9 * len(names)),
                                     squeeze=False, sharey=True)
            for i, name in enumerate(names):
                sel = which == name
                for j, law in enumerate(laws):
                    ax = axes[i][j]
                    ax.plot(1e3 * col["x [m]"][sel], 1e-3 * col["F measured [N]"][sel], color=MEASURED_COLOR,
                            lw=0.6, label="measured")
                    ax.plot(1e3 * col["x [m]"][sel], 1e-3 * col[f"F {law} [N]"][sel], color=_style.color(law),
                            lw=0.9, label=f"{LAW_NAMES.get(law, law)} (predicted)")
                    if i == 0:
                        ax.set_title(LAW_NAMES.get(law, law))
                    if i == len(names) - 1:
                        ax.set_xlabel("displacement [mm]")
                    if j == 0:
                        ax.set_ylabel(f"{name.replace('sine_', '').replace('_', ', ')}\nforce [kN]")
            fig.suptitle(f"Held-out records at {g}: measured (grey), predicted")
            files += _save(fig, outdir / f"identify_loops_{g}")
            width = RESIDUALS_WIDTH
            _style.apply(width)
            fig, axes = plt.subplots(len(laws), 1, figsize=(width, 1.0 + 1.9 * len(laws)), squeeze=False,
                                     sharex=True)
            for i, law in enumerate(laws):
                ax = axes[i][0]
                offset = 0.0
                for name in names:
                    sel = which == name
                    tt = col["t [s]"][sel]
                    ax.plot(offset + tt, 1e-3 * (col[f"F {law} [N]"][sel] - col["F measured [N]"][sel]),
                            color=_style.color(law), lw=0.5)
                    ax.axvline(offset, color="k", lw=0.4)
                    offset += tt[-1] + 0.5
                ax.set_ylabel(f"{LAW_NAMES.get(law, law)}\nresidual [kN]")
            axes[-1][0].set_xlabel("time [s], held-out records in turn (lines: starts)")
            fig.suptitle(f"Residual force (predicted - measured) at {g}")
            files += _save(fig, outdir / f"identify_residuals_{g}")
        # the chosen law's parameter correlations (run() writes them: a result of the fit)
        corr_path = outdir / f"identify_correlation_{g}.csv"
        if corr_path.exists():
            cc = c.read_csv(corr_path)
            labels = cc["parameter [-]"]
            m = np.array([[float(x) for x in cc[f"{k} [-]"]] for k in labels])
            width = CORRELATION_WIDTH
            _style.apply(width)
            fig, ax = plt.subplots(figsize=(width, 0.9 * width))
            im = ax.imshow(m, vmin=-1, vmax=1, cmap="PuOr")
            ax.set_xticks(range(len(labels)), labels, rotation=60, ha="right")
            ax.set_yticks(range(len(labels)), labels)
            ax.grid(False)
            for (i, j), val in np.ndenumerate(m):
                ax.text(j, i, f"{val:.2f}", ha="center", va="center",
                        color="white" if abs(val) > 0.6 else "black")
            fig.colorbar(im, ax=ax, label="correlation of the estimates [-]")
            ax.set_title(f"{LAW_NAMES.get(chosen, chosen)} at {g}: correlations")
            files += _save(fig, outdir / f"identify_correlation_{g}")
    files += plot_scores(outdir / "identify_scores.csv", outdir)
    return files


def plot_scores(csv: str | Path, outdir: str | Path) -> list[Path]:
    """The scores of every law (identify_scores.csv): the RMS errors (held out: bars, fitted:
    ticks) and the BIC above the best, a colour per group; axes fitted to the data and one
    legend below the panels (it covers no data)."""
    import matplotlib.pyplot as plt
    scores = _rows(Path(csv))
    groups = sorted({r["group [-]"] for r in scores})
    laws = list(dict.fromkeys(r["law [-]"] for r in scores))
    width = SCORES_WIDTH
    _style.apply(width)
    fig, axes = plt.subplots(2, 1, figsize=(width, 2.0 * width), sharex=True)
    width = 0.8 / max(len(groups), 1)
    errors: list[float] = []
    bics: list[float] = []
    for k, g in enumerate(groups):
        mine = {r["law [-]"]: r for r in scores if r["group [-]"] == g}
        xs = np.arange(len(laws)) + (k - 0.5 * (len(groups) - 1)) * width
        held = [float(mine[l]["nrmse held out [-]"] or "nan") for l in laws]
        fitted = [float(mine[l]["nrmse fitted [-]"]) for l in laws]
        bic = [float(mine[l]["delta BIC [-]"]) + 1.0 for l in laws]
        errors += [100 * v for v in held + fitted if np.isfinite(v)]
        bics += bic
        axes[0].bar(xs, 100 * np.array(held), width, color=GROUP_COLORS[k % len(GROUP_COLORS)],
                    label=g)
        axes[0].plot(xs, 100 * np.array(fitted), "k_", ms=8, label="fitted" if k == 0 else None)
        # points, not bars, on the log axis (a bar's length from an arbitrary baseline means nothing)
        axes[1].semilogy(xs, bic, "o", ms=5, color=GROUP_COLORS[k % len(GROUP_COLORS)], label=g)
    axes[1].set_xticks(range(len(laws)), [LAW_NAMES.get(l, l).split(" (")[0] for l in laws], rotation=90)
    axes[0].set_ylabel("RMS error / force range [%]")
    axes[0].set_title("error: held out (bars), fitted (ticks)")
    axes[0].set_ylim(0.0, 1.08 * max(errors))             # axes fitted to the data
    axes[1].set_ylabel("BIC - best BIC + 1 [-]")
    axes[1].set_title("BIC of the fits (lower: better)")
    axes[1].set_ylim(min(bics) / 2.0, max(bics) * 2.0)
    c.log_ticks(axes[1], "y")
    c.figure_legend(fig, axes, ncol=len(groups) + 1)
    png = c.save_figure(fig, Path(outdir) / "identify_scores.png")
    return [png, png.with_suffix(".pdf")]


def write_correlations(outdir: Path, results: list[dict[str, Any]], scores_path: Path) -> list[Path]:
    """The chosen law's correlation matrix per group, as CSV."""
    scores = _rows(scores_path)
    files = []
    for g in sorted({r["group"] for r in results}):
        chosen, _ = choose(scores, g)
        fit = next(r["fit"] for r in results if r["group"] == g and r["law"] == chosen)
        rows = [[name, *fit.correlation[i]] for i, name in enumerate(fit.free)]
        files.append(c.write_csv(outdir / f"identify_correlation_{g}.csv",
                                 ["parameter [-]", *(f"{n} [-]" for n in fit.free)], rows))
    return files


def report(outdir: str | Path, split_note: str) -> Path:
    """The Markdown report: which law to use and why, from the CSV files."""
    outdir = Path(outdir)
    scores = _rows(outdir / "identify_scores.csv")
    params = _rows(outdir / "identify_params.csv")
    groups = sorted({r["group [-]"] for r in scores})
    out = ["# Friction-law identification", "",
           "Written by `python -m cases.identify`. Each law fitted by `stickslip.fit_friction` "
           "(backlash and asymmetry fitted too; force levels in N, the normal force not being "
           "measured). " + split_note, ""]
    for g in groups:
        chosen, ranked = choose(scores, g)
        mine = {r["law [-]"]: r for r in ranked}
        pct = lambda law, col: f"{100 * float(mine[law][col]):.1f} %" if law in mine and mine[law][col] else "n/a"  # noqa: E731
        out += [f"## {g}", ""]
        bic_best = min(ranked, key=lambda r: float(r["BIC [-]"]))["law [-]"]
        best = ranked[0]["law [-]"]
        why = ("the lowest held-out error" if chosen == best else
               f"the fewest parameters among the laws within {100 * TIE:.0f} % (relative) of the lowest "
               f"held-out error ({LAW_NAMES.get(best, best)}, {pct(best, 'nrmse held out [-]')})")
        out.append(f"**Use {LAW_NAMES.get(chosen, chosen)}** (`{chosen}`), {why}: held-out error "
                   f"{pct(chosen, 'nrmse held out [-]')} of the force range, against "
                   f"{pct(STATIC_REFERENCE, 'nrmse held out [-]')} for the static law "
                   f"{LAW_NAMES[STATIC_REFERENCE]} and {pct('dahl', 'nrmse held out [-]')} for Dahl's. "
                   f"BIC on the fitted records prefers {LAW_NAMES.get(bic_best, bic_best)} (`{bic_best}`).")
        out.append("")
        out.append(c.markdown_table(
            ["law", "fitted parameters", "nrmse fitted", "nrmse held out", "rmse held out [N]", "delta BIC", "fit time [s]"],
            [[f"`{r['law [-]']}`", r["fitted parameters [-]"], f"{100 * float(r['nrmse fitted [-]']):.1f} %",
              f"{100 * float(r['nrmse held out [-]']):.1f} %" if r["nrmse held out [-]"] else "",
              f"{float(r['rmse held out [N]']):.0f}" if r["rmse held out [N]"] else "",
              f"{float(r['delta BIC [-]']):.0f}", f"{float(r['fit time [s]']):.1f}"] for r in ranked]))
        out.append(f"Parameters of `{chosen}` (95 % intervals assume independent noise; the damper's is "
                   "not, so they are too narrow: read them as the precision of the fit, not of the device):")
        out.append("")
        out.append(c.markdown_table(
            ["parameter", "value", "unit", "95 % interval"],
            [[p["parameter [-]"], float(p["value [unit]"]), p["unit [-]"],
              (f"[{float(p['ci95 low [unit]']):.4g}, {float(p['ci95 high [unit]']):.4g}]"
               + (" (at a bound)" if p["at bound [-]"] == "1" else "")) if p["fitted [-]"] == "1" else "fixed"]
             for p in params if p["group [-]"] == g and p["law [-]"] == chosen]))
        out.append(f"Figures: `identify_loops_{g}.png`, `identify_residuals_{g}.png`, "
                   f"`identify_correlation_{g}.png`; all laws: `identify_scores.png`.")
        out.append("")
    return c.write_text(outdir / "identify_report.md", "\n".join(out))


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.identify [--data FILES...] [--laws LAWS...] [--outdir DIR]."""
    import stickslip
    parser = argparse.ArgumentParser(prog="python -m cases.identify", description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", nargs="+", type=Path, default=None, metavar="FILE",
                        help="record files (CSV or .csv.gz with t [s], x [m], F [N], optional v [m/s]; "
                             "default: the repository's data/friction-damper/*.csv.gz)")
    parser.add_argument("--laws", nargs="+", choices=stickslip.LAWS, default=None, metavar="LAW",
                        help=f"candidate laws (default: all, {' '.join(stickslip.LAWS)})")
    c.add_outdir(parser, help="directory for CSV, PNG, PDF and Markdown files (default: out/)")
    parser.add_argument("--threads", type=c.count, default=2,
                        help="fits run at once, each in its own process, >= 1 (default 2)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    for f in args.data or ():
        if not f.is_file():
            parser.error(f"argument --data: {f}: no such file")
        try:
            stickslip.load_damper_record(f)
        except (ValueError, OSError, EOFError) as exc:
            parser.error(f"argument --data: {f}: {' '.join(str(exc).split())}")
    t0 = time.perf_counter()
    files = run(args.outdir, files=args.data, laws=args.laws, workers=args.threads, quiet=args.quiet)
    files += plot(args.outdir)
    files.append(report(args.outdir, SPLIT_NOTE))
    c.log(f"cases.identify: {time.perf_counter() - t0:.1f} s", args.quiet)
    return c.finish("cases.identify", argv, files)


SPLIT_NOTE = ("Records grouped by band tension, each group fitted on its own; within a group the "
              "records are split as a checkerboard of frequency x amplitude (fitted when the sum of the "
              "two indices is even, held out otherwise), so every frequency and amplitude is on both "
              f"sides. Records subsampled to {SAMPLES_PER_CYCLE} samples per cycle.")


if __name__ == "__main__":
    main()
