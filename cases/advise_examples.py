"""The advisor guide's examples and its brute-force table, run (docs/guide/advisor.md embeds
these files, so the page shows what the code answers today)::

    python -m cases.advise_examples --outdir out/

Writes advise_belt_stribeck.md (the printed advice for the page's first example),
advise_slope_coulomb_eventfree.md (Coulomb on the slope with the event-free methods alone: no
method can), advise_slope_coulomb.md (the same with every method: the held box) and
advise_check.csv (the brute-force check of the advice on parameter sets no study used: the
advised method and setting, its estimated and true error, its cost over the cheapest setting of
a grid search, and the cost of all the advisor's runs over the advised run's). --quick checks
two problems instead of nine.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

from . import _common as c

BELT: dict[str, float] = dict(k=450.0, m=3.0, v_b=0.8)          # no study used these
STRIBECK: dict[str, float] = dict(mu_s=0.4, mu_k=0.25, v_s=0.05, delta=1.5, v_eps=2e-3)

#: The printed examples: file stem -> (scene, law, target [m], t_end [s], keywords).
EXAMPLES: dict[str, tuple[str, str, float, float, dict[str, Any]]] = {
    "advise_belt_stribeck": ("belt", "stribeck", 1e-6, 10.0, dict(BELT)),
    "advise_slope_coulomb_eventfree": ("slope", "coulomb", 1e-6, 5.0,
                                       dict(methods=("rk4", "dopri5", "dop853", "radau5"))),
    "advise_slope_coulomb": ("slope", "coulomb", 1e-6, 5.0, {}),
}

#: The brute-force checks: (problem as shown, scene, law, target [m], t_end [s], keywords).
CHECKS: tuple[tuple[str, str, str, float, float, dict[str, Any]], ...] = (
    ("belt, Stribeck, from rest, 10 s", "belt", "stribeck", 1e-4, 10.0, dict(BELT, **STRIBECK)),
    ("belt, Stribeck, from rest, 10 s", "belt", "stribeck", 1e-6, 10.0, dict(BELT, **STRIBECK)),
    ("belt, Stribeck, from rest, 10 s", "belt", "stribeck", 1e-9, 10.0, dict(BELT, **STRIBECK)),
    ("slope 25 deg, Stribeck, from rest, 3 s", "slope", "stribeck", 1e-5, 3.0,
     dict(STRIBECK, theta_deg=25.0)),
    ("slope 25 deg, Stribeck, from rest, 3 s", "slope", "stribeck", 1e-8, 3.0,
     dict(STRIBECK, theta_deg=25.0)),
    ("belt, proposed, started stuck (v0 = 0.8 m/s), 6 s", "belt", "proposed", 1e-5, 6.0,
     dict(BELT, v0=0.8)),
    ("belt, proposed, started stuck (v0 = 0.8 m/s), 6 s", "belt", "proposed", 1e-7, 6.0,
     dict(BELT, v0=0.8)),
    ("slope 8 deg, RecurDyn, v_s = 5 mm/s, creeping, 15 s", "slope", "recurdyn", 1e-8, 15.0,
     dict(theta_deg=8.0, v_s=5e-3)),
    ("belt, LuGre, from rest, 5 s", "belt", "lugre", 1e-6, 5.0, dict(BELT)),
)
QUICK_CHECKS: tuple[int, ...] = (0, 8)


def printed(scene: str, law: str, target: float, t_end: float, kw: dict[str, Any]) -> str:
    """The advice as `python -m cases.advise` prints it, in a fenced text block with the call."""
    import stickslip as ss
    a = ss.advise(scene, law, target, t_end, **kw)
    call = ", ".join([repr(scene), repr(law), f"{target:g}", f"{t_end:g}"]
                     + [f"{k}={v!r}" if not isinstance(v, float) else f"{k}={v:g}" for k, v in kw.items()])
    return f"```text\n>>> print(ss.advise({call}))\n{a}```\n"


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """Run the examples and the checks; write the files of the module's docstring."""
    import stickslip as ss
    from .advise import compare
    from stickslip.advise import error_text
    outdir = Path(outdir)
    files = []
    for stem, (scene, law, target, t_end, kw) in EXAMPLES.items():
        c.log(f"advise_examples: {stem}", quiet)
        files.append(c.write_text(outdir / f"{stem}.md", printed(scene, law, target, t_end, kw)))
    rows = []
    for i, (problem, scene, law, target, t_end, kw) in enumerate(CHECKS):
        if quick and i not in QUICK_CHECKS:
            continue
        c.log(f"advise_examples: {problem}, target {target:g} m", quiet)
        kw = dict(kw)
        x0, v0 = kw.pop("x0", 0.0), kw.pop("v0", 0.0)
        a = ss.advise(scene, law, target, t_end, x0=x0, v0=v0, **kw)
        cmp = compare(a)
        setting = "" if not a.feasible else (f"h {a.controls['h']:.3g} s" if "h" in a.controls
                                             else f"rtol {a.controls['rtol']:.2g}")
        rows.append([problem, f"{target:g}", a.method or "none", setting,
                     error_text(a.predicted_error, a.roundoff),
                     "" if cmp["true_error"] is None else f"{cmp['true_error']:.2g}",
                     "" if cmp["cost_ratio"] is None else f"{cmp['cost_ratio']:.2f}",
                     "" if a.pilot_cost.get("ratio") is None else f"{a.pilot_cost['ratio']:.0f}"])
    files.append(c.write_csv(outdir / "advise_check.csv",
                             ["problem [-]", "target [m]", "advised [-]", "setting [-]", "estimated error [m]",
                              "true error [m]", "cost / cheapest [-]", "all runs / advised run [-]"], rows))
    return files


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.advise_examples [--outdir DIR] [--quick] [--quiet]."""
    return c.study_main("cases.advise_examples", __doc__,
                        "check two problems instead of nine", run, argv)


if __name__ == "__main__":
    main()
