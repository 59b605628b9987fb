"""Gallery: a two-degree-of-freedom belt system of the Popp-Stelter kind
(docs/gallery/belt-2dof.md): where a regularised law's stick-slip differs from the exact one::

    python -m cases.gallery_belt2dof --outdir docs/figures

Two 1 kg blocks on a belt moving at 0.2 m/s, each held by a spring to the wall (400 and
250 N/m) and coupled by a 100 N/m spring; Stribeck friction on both (normal force 9.81 N,
mu_s = 0.4, mu_k = 0.25, v_s = 0.05 m/s, delta = 2), from rest. The exact motion is
`event_driven` (set-valued: the blocks stick to the belt exactly); the regularised ones are the
same `stribeck` law smoothed with tanh(s / v_eps) at four widths v_eps, run by DOPRI5 at rtol
1e-9, and the paper's `proposed` law (Roh & Yoo's) at its default. Over the last 6 s of 10 s
(the transient left out) each run gives block 1's mean period (mean time between its
up-crossings of its mean position: the motion is not periodic), its amplitude (half the
peak-to-peak) and its stick fraction (the share of time with abs(slip) < 1 mm/s), and the
largest deviation of block 1's position from the exact one over the whole run.

Writes gallery_belt2dof.csv (block 1's speed of each run over the last 1.5 s),
gallery_belt2dof_errors.csv (the three measures' relative errors at each v_eps),
gallery_belt2dof.png (drawn from the two CSVs alone: speeds, and the relative errors against
v_eps) and gallery_belt2dof.md (the table). --quick leaves out the narrowest width.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness import style as _style

from . import _common as c
from . import _gallery

G: float = 9.81
V_BELT: float = 0.2
M1, M2, K1, K2, K12 = 1.0, 1.0, 400.0, 250.0, 100.0
LAW: dict[str, float] = dict(mu_s=0.4, mu_k=0.25, v_s=0.05, delta=2.0)
T_END, T_SKIP = 10.0, 4.0
N_OUT: int = 20001
STICK_BELOW: float = 1e-3
WIDTHS: tuple[float, ...] = (1e-2, 1e-3, 1e-4, 1e-5)


def model(law: str = "stribeck", **params: float) -> Any:
    """The two blocks (bodies 0 and 1) on the belt, each contact with `law` (and `params` over
    the Stribeck parameters above, which a law without them does not take)."""
    import stickslip as ss
    m = ss.Model()
    b1 = m.add_body(M1, name="block1")
    b2 = m.add_body(M2, name="block2")
    m.add_spring(b1, None, k=K1)
    m.add_spring(b2, None, k=K2)
    m.add_spring(b1, b2, k=K12)
    for b, mass in ((b1, M1), (b2, M2)):
        m.add_contact(b, None, law, normal_force=mass * G, surface_velocity=V_BELT, **params)
    return m


def measures(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> dict[str, float]:
    """Block 1's period [s], amplitude [m] and stick fraction [-] after T_SKIP."""
    keep = t >= T_SKIP
    t, x, v = t[keep], x[keep], v[keep]
    mid = 0.5 * (x.max() + x.min())
    up = np.flatnonzero((x[:-1] < mid) & (x[1:] >= mid))
    tc = t[up] + (mid - x[up]) / (x[up + 1] - x[up]) * (t[up + 1] - t[up])
    period = float(np.mean(np.diff(tc))) if tc.size > 1 else float("nan")
    return {"period": period, "amplitude": float(0.5 * (x.max() - x.min())),
            "stick": float(np.mean(np.abs(v - V_BELT) < STICK_BELOW))}


def runs(quick: bool, quiet: bool) -> list[tuple[str, float, Any]]:
    """(label, width or nan, result) of the exact run and the regularised ones."""
    import stickslip as ss
    out = []
    c.log("gallery_belt2dof: event_driven (exact)", quiet)
    out.append(("Stribeck, exact (event_driven)", float("nan"),
                ss.simulate(model(**LAW), method="event_driven", t_end=T_END, n_out=N_OUT, rtol=1e-10, atol=1e-12)))
    for w in WIDTHS[:-1] if quick else WIDTHS:
        c.log(f"gallery_belt2dof: stribeck, v_eps = {w:g} m/s (DOPRI5)", quiet)
        out.append((f"Stribeck, v_eps = {w:g} m/s (DOPRI5)", w,
                    ss.simulate(model(**LAW, v_eps=w), method="dopri5", t_end=T_END, n_out=N_OUT,
                                rtol=1e-9, atol=1e-12, max_steps=50_000_000)))
    c.log("gallery_belt2dof: proposed (DOPRI5)", quiet)
    out.append(("proposed (Roh & Yoo), default (DOPRI5)", float("nan"),
                ss.simulate(model("proposed", mu_s=LAW["mu_s"], mu_k=LAW["mu_k"]), method="dopri5", t_end=T_END,
                            n_out=N_OUT, rtol=1e-9, atol=1e-12, max_steps=50_000_000)))
    return out


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """Run the exact and the regularised motions; write the files of the module's docstring."""
    outdir = Path(outdir)
    results = runs(quick, quiet)
    exact = measures(results[0][2].t, results[0][2].x[0], results[0][2].v[0])
    rows, rel = [], []
    x_exact = results[0][2].x[0]
    for label, width, res in results:
        mm = measures(res.t, res.x[0], res.v[0])
        err = {k: (mm[k] - exact[k]) / exact[k] for k in ("period", "amplitude", "stick")}
        rel.append((width, err))
        rows.append([label, f"{mm['period']:.5f}", f"{1e3 * mm['amplitude']:.4f}", f"{mm['stick']:.3f}",
                     "" if label.startswith("Stribeck, exact") else f"{100 * err['period']:+.2g}",
                     "" if label.startswith("Stribeck, exact") else f"{100 * err['amplitude']:+.2g}",
                     "" if label.startswith("Stribeck, exact") else f"{1e3 * np.abs(res.x[0] - x_exact).max():.2g}",
                     f"{res.stats['nfev']}"])
    files = [c.write_text(outdir / "gallery_belt2dof.md", c.markdown_table(
        ["run", "mean period [s]", "amplitude [mm]", "stick fraction [-]", "period error [%]",
         "amplitude error [%]", "max abs(x1 − x1_exact) [mm]", "right-hand sides [-]"], rows))]
    t = results[0][2].t
    last = t >= T_END - 1.5
    cols = {"time t [s]": t[last]}
    for label, _, res in results:
        cols[f"v1 {label} [m/s]"] = res.v[0][last]
    files.append(c.write_columns(outdir / "gallery_belt2dof.csv", cols))
    widths = [(w, e) for w, e in rel if np.isfinite(w)]
    files.append(c.write_columns(outdir / "gallery_belt2dof_errors.csv", {
        "v_eps [m/s]": np.array([w for w, _ in widths]),
        **{f"{name} relative error [-]": np.array([e[key] for _, e in widths]) for key, name in MEASURES}}))
    files.append(plot(outdir / "gallery_belt2dof.csv", outdir / "gallery_belt2dof_errors.csv",
                      outdir / "gallery_belt2dof.png"))
    return files


#: The measures of a run: (key of `measures`, name in the figure and the errors' CSV).
MEASURES: tuple[tuple[str, str], ...] = (("period", "mean period"), ("amplitude", "amplitude"),
                                         ("stick", "stick fraction"))


def plot(series: Path, errors: Path, path: Path) -> Path:
    """From the CSVs alone (`series`: gallery_belt2dof.csv, `errors`:
    gallery_belt2dof_errors.csv): top, block 1's speed over the last 1.5 s (exact and two
    widths); bottom, the measures' relative errors against v_eps."""
    cols, rel = c.read_numeric_csv(series), c.read_numeric_csv(errors)
    fig, top, bottom = _gallery.two_panels(5.4)
    t = cols["time t [s]"]
    series = [k for k in cols if k.startswith("v1 Stribeck")]
    shown = [series[0]] + [k for k in series[1:] if "0.01 " in k or "0.001 " in k]
    colors = (_style.OKABE_ITO["black"], _style.OKABE_ITO["vermillion"], _style.OKABE_ITO["sky blue"])
    for k, color, style in zip(shown, colors, ("-", "--", ":")):
        label = k[3:].replace(" [m/s]", "").replace("Stribeck, ", "").replace(" (DOPRI5)", "") \
            .replace("(event_driven)", "(event-driven)")
        top.plot(t, cols[k], color=color, linestyle=style, label=label, lw=1.1 if style == "-" else 1.3)
    top.axhline(V_BELT, color="0.6", lw=0.6)
    top.set_xlabel("time t [s]")
    top.set_ylabel("speed of block 1 [m/s]")
    top.set_title("Two blocks on a belt: Stribeck friction")
    _gallery.legend_above_data(top, ncol=1, room=0.8)
    for (_, name), marker, color in zip(MEASURES, "os^", _style.SEQUENCE):
        e = np.abs(rel[f"{name} relative error [-]"])
        bottom.loglog(rel["v_eps [m/s]"], np.maximum(e, 1e-6), marker=marker, color=color, label=name, ms=4)
    bottom.set_xlabel("regularisation width v_eps [m/s]")
    bottom.set_ylabel("abs(relative error) [-]")
    bottom.legend(loc="lower right")
    return _gallery.save(fig, path)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_belt2dof [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_belt2dof", __doc__, "leave out the narrowest width", run, argv)


if __name__ == "__main__":
    main()
