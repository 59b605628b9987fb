"""Gallery: stacked blocks on a belt and a block on redundant feet (docs/gallery/stacked-blocks.md),
built with `ss.Model`, against closed forms and an independent scipy event-driven solver::

    python -m cases.gallery_stacked --outdir docs/figures

Block A (1 kg, a 100 N/m spring to the wall) lies on a belt moving at 0.2 m/s; block B (0.5 kg,
a 40 N/m spring to the wall) lies on A. Coulomb friction, mu_s = 0.5, mu_k = 0.3 on the belt
(normal force (m_A + m_B) g). Three systems:

- **stacked, B held**: B's contact holds (mu_s = mu_k = 5): A and B move as one block of
  1.5 kg on a 140 N/m spring, whose stick-slip cycle on the belt has a closed form.
- **stacked, B slips**: B's contact mu_s = 0.25, mu_k = 0.2: B slips on A while A sticks to
  and slips on the belt; the reference is the scipy event-driven solver of
  cases/_scipy_events.py (exhaustive mode search).
- **feet**: one 1 kg block on a 100 N/m spring on two feet, each a contact with the belt
  carrying half the weight: a redundant pair (the contact forces are not unique, the motion
  is), the same closed form as one contact with the whole weight.

Writes gallery_stacked.csv (positions of the three systems: event_driven and their
references), gallery_stacked_convergence.csv (moreau's largest deviation from each reference
at each step size), gallery_stacked.png (drawn from the two CSVs alone: motion and
Moreau-Jean's convergence), gallery_stacked.md (the largest deviations of event_driven and of
moreau at four step sizes from each reference, with the fitted order). --quick leaves out the
smallest Moreau step.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from harness import style as _style

from . import _common as c
from . import _gallery

G: float = 9.81
V_BELT: float = 0.2
M_A, M_B, K_A, K_B = 1.0, 0.5, 100.0, 40.0
MU_S, MU_K = 0.5, 0.3
#: B's contact on A: (mu_s, mu_k) of the held and of the slipping case.
B_HELD, B_SLIPS = (5.0, 5.0), (0.25, 0.2)
T_END: float = 3.0
N_OUT: int = 601
STEPS: tuple[float, ...] = (1e-2, 1e-3, 1e-4, 1e-5)


def stacked(b_mu: tuple[float, float]) -> Any:
    """The stacked blocks: bodies A (0) and B (1); contacts A-belt (0) and B-A (1)."""
    import stickslip as ss
    m = ss.Model()
    a = m.add_body(M_A, name="A")
    b = m.add_body(M_B, name="B")
    m.add_spring(a, None, k=K_A)
    m.add_spring(b, None, k=K_B)
    m.add_contact(a, None, "coulomb", normal_force=(M_A + M_B) * G, surface_velocity=V_BELT,
                  mu_s=MU_S, mu_k=MU_K)
    m.add_contact(b, a, "coulomb", normal_force=M_B * G, mu_s=b_mu[0], mu_k=b_mu[1])
    return m


def feet(n_feet: int = 2) -> Any:
    """A 1 kg block on a 100 N/m spring on `n_feet` feet on the belt, each carrying its share."""
    import stickslip as ss
    m = ss.Model()
    a = m.add_body(M_A, name="block")
    m.add_spring(a, None, k=K_A)
    for _ in range(n_feet):
        m.add_contact(a, None, "coulomb", normal_force=M_A * G / n_feet, surface_velocity=V_BELT,
                      mu_s=MU_S, mu_k=MU_K)
    return m


def closed_form(t: np.ndarray, m: float, k: float, normal: float, v_b: float = V_BELT,
                mu_s: float = MU_S, mu_k: float = MU_K) -> np.ndarray:
    """Position of a block (mass m, spring k to the wall, at rest at x = 0 at t = 0) on a belt
    moving at v_b with Coulomb friction (normal force `normal`) [m]. It slips (friction mu_k N
    forwards) until it reaches the belt's speed, sticks until k x = mu_s N, then slips one arc
    about x_k = mu_k N / k back to the belt's speed at x = 2 x_k - x_s, and so on."""
    w = math.sqrt(k / m)
    x_k, x_s = mu_k * normal / k, mu_s * normal / k
    if x_k * w <= v_b:
        raise ValueError("closed_form: the first slip must reach the belt's speed (x_k w > v_b)")
    t1 = math.asin(v_b / (x_k * w)) / w                  # first arrival at the belt's speed
    x1 = x_k * (1.0 - math.cos(w * t1))
    d = x_s - x_k
    amp = d * w / v_b
    slip = (2.0 * math.pi - 2.0 * math.atan(amp)) / w     # one slip arc from x_s back to v_b
    x_end = 2.0 * x_k - x_s
    out = np.empty_like(t, dtype=float)
    for i, tt in enumerate(np.asarray(t, float)):
        if tt <= t1:
            out[i] = x_k * (1.0 - math.cos(w * tt))
            continue
        first_stick = (x_s - x1) / v_b
        if tt <= t1 + first_stick:
            out[i] = x1 + v_b * (tt - t1)
            continue
        tau = (tt - t1 - first_stick) % (slip + 2.0 * d / v_b)
        if tau <= slip:
            out[i] = x_k + d * math.cos(w * tau) + v_b / w * math.sin(w * tau)
        else:
            out[i] = x_end + v_b * (tau - slip)
    return out


def scipy_stacked(b_mu: tuple[float, float], t: np.ndarray) -> np.ndarray:
    """Positions (2, n_t) of the stacked blocks by the scipy event-driven solver."""
    from cases._scipy_events import ScipyContacts

    def force(_t: float, x: np.ndarray) -> np.ndarray:
        return np.array([-K_A * x[0], -K_B * x[1]])

    n_a, n_b = (M_A + M_B) * G, M_B * G
    sysm = ScipyContacts([M_A, M_B], force, [(0, None, lambda _t: n_a, V_BELT), (1, 0, lambda _t: n_b)],
                         [MU_S, b_mu[0]], [MU_K, b_mu[1]])
    x, _, _ = sysm.run([0.0, 0.0], T_END, t, rtol=1e-12, atol=1e-14)
    return x


def order(hs: Sequence[float], errs: Sequence[float]) -> float:
    """The slope of log(error) over log(h) (least squares)."""
    return float(np.polyfit(np.log(hs), np.log(errs), 1)[0])


def run(outdir: str | Path, *, quick: bool = False, threads: int = 2, quiet: bool = False) -> list[Path]:
    """Run the three systems; write the files of the module's docstring."""
    import stickslip as ss
    outdir = Path(outdir)
    t = np.linspace(0.0, T_END, N_OUT)
    steps = STEPS[:-1] if quick else STEPS
    cases = {
        "stacked, B held": (stacked(B_HELD),
                            lambda: np.vstack([closed_form(t, M_A + M_B, K_A + K_B, (M_A + M_B) * G)] * 2),
                            "closed form (one block of 1.5 kg)"),
        "stacked, B slips": (stacked(B_SLIPS), lambda: scipy_stacked(B_SLIPS, t), "scipy event-driven"),
        "feet (2 contacts, N/2 each)": (feet(2), lambda: closed_form(t, M_A, K_A, M_A * G)[None, :],
                                        "closed form (one contact, N)"),
    }
    rows, cols, conv = [], {"time t [s]": t}, {}
    for label, (model, reference, ref_name) in cases.items():
        c.log(f"gallery_stacked: {label}", quiet)
        ref = reference()
        ed = ss.simulate(model, method="event_driven", t_end=T_END, n_out=N_OUT, rtol=1e-12, atol=1e-14)
        errs = []
        for h in steps:
            r = ss.simulate(model, method="moreau", h=h, t_end=T_END, n_out=N_OUT)
            errs.append(float(np.abs(r.x - ref).max()))
        conv[label] = errs
        rows.append([label, ref_name, f"{np.abs(ed.x - ref).max():.1g}", f"{ed.stats['nevents']}"]
                    + [f"{e:.2g}" for e in errs] + [f"{order(steps, errs):.2f}"])
        for i in range(ref.shape[0]):
            name = model.label(i)
            cols[f"x {label} {name} event_driven [m]"] = ed.x[i]
            cols[f"x {label} {name} reference [m]"] = ref[i]
    # the redundant pair against one contact with the whole weight, both event-driven
    one = ss.simulate(feet(1), method="event_driven", t_end=T_END, n_out=N_OUT, rtol=1e-12, atol=1e-14)
    two = ss.simulate(feet(2), method="event_driven", t_end=T_END, n_out=N_OUT, rtol=1e-12, atol=1e-14)
    feet_vs_one = float(np.abs(two.x - one.x).max())
    header = (["system", "reference", "event_driven: max abs(x − x_ref) [m]", "events [-]"]
              + [f"moreau h = {h:g} s [m]" for h in steps] + ["moreau's order [-]"])
    text = c.markdown_table(header, rows) + (
        f"\nThe block on two feet against the same block on one foot with the whole weight (both "
        f"event_driven, rtol 1e-12): max abs(x_two − x_one) = {feet_vs_one:.1g} m.\n")
    files = [c.write_text(outdir / "gallery_stacked.md", text),
             c.write_columns(outdir / "gallery_stacked.csv", cols),
             c.write_columns(outdir / "gallery_stacked_convergence.csv", {
                 "h [s]": np.array(steps), **{f"max error {label} [m]": np.array(errs) for label, errs in conv.items()}}),
             plot(outdir / "gallery_stacked.csv", outdir / "gallery_stacked_convergence.csv",
                  outdir / "gallery_stacked.png")]
    return files


def plot(positions: Path, convergence: Path, path: Path) -> Path:
    """From the CSVs alone (`positions`: gallery_stacked.csv, `convergence`:
    gallery_stacked_convergence.csv): top, the stacked blocks' positions (B slipping),
    event_driven as lines, the scipy reference as dots; bottom, Moreau-Jean's largest error
    against the step size."""
    cols, errors = c.read_numeric_csv(positions), c.read_numeric_csv(convergence)
    t, steps = cols["time t [s]"], errors["h [s]"]
    conv = {c.split_unit(k)[0].removeprefix("max error "): v for k, v in errors.items() if k != "h [s]"}
    fig, top, bottom = _gallery.two_panels(5.6)
    for body, color in (("A", _style.SEQUENCE[0]), ("B", _style.SEQUENCE[1])):
        top.plot(t, 1e3 * cols[f"x stacked, B slips {body} event_driven [m]"], color=color, label=f"block {body}")
        top.plot(t[::12], 1e3 * cols[f"x stacked, B slips {body} reference [m]"][::12], "o", ms=2.5,
                 mfc="none", color=color)
    top.plot([], [], "o", ms=2.5, mfc="none", color="0.3", label="scipy reference")
    top.set_xlabel("time t [s]")
    top.set_ylabel("position x [mm]")
    top.set_title("Stacked blocks on a belt (B slips on A)")
    _gallery.legend_above_data(top, ncol=2, room=0.5)
    markers = ("o", "s", "^")
    for i, (label, errs) in enumerate(conv.items()):
        bottom.loglog(steps, errs, marker=markers[i], color=_style.SEQUENCE[i + 2], label=label, ms=4)
    h = np.array([steps[0], steps[-1]])
    bottom.loglog(h, conv[next(iter(conv))][0] * h / h[0], ":", color="0.5", label="slope 1")
    bottom.set_xlabel("Moreau-Jean step h [s]")
    bottom.set_ylabel("max abs(x − x_ref) [m]")
    bottom.legend(loc="upper center", bbox_to_anchor=(0.5, -0.28), ncol=2, frameon=False,
                  handlelength=1.5, columnspacing=0.8)     # below the panel: the lines cross it
    return _gallery.save(fig, path)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Command line: python -m cases.gallery_stacked [--outdir DIR] [--quick] [--threads N] [--quiet]."""
    return c.study_main("cases.gallery_stacked", __doc__, "leave out the smallest Moreau step", run, argv)


if __name__ == "__main__":
    main()
