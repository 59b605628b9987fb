"""Every law x every method on a small general model, into model_law_method.csv::

    python -m cases.model_pairs --outdir docs/figures/     # about 20 s on one core

The model (`general_model`): two bodies of 1 and 2 kg, a spring of 50 N/m from body 0 to the
ground and one of 80 N/m between them, a force on body 1 that steps from 0 to 4 N at 0.3 s, a
contact of body 0 with a surface moving at 0.3 m/s (normal force 9.81 N) and one between the
bodies (normal force 5 N), both with the row's law and its default parameters; body 0 starts
at 0.5 m/s, 1 s is simulated. Fixed-step methods run at h = 1e-3 s, adaptive ones at the
defaults of `stickslip.simulate` with at most MAX_STEPS steps. Each cell is the run's outcome:
"ok" (t_end reached), "refused" (a ValueError before running: the method does not take the
law on a model) or the name of the IntegrationError it ended with. The table is a pivot: a row
per law, a column per method. tests/test_sweep.py runs every pair again and checks it
ends as the committed file says.
"""
from __future__ import annotations

import warnings
from pathlib import Path
from typing import Sequence

from . import _common as c

T_END: float = 1.0
H: float = 1e-3
MAX_STEPS: int = 200_000


def general_model(law: str, **law_params: float):
    """The small general model of the module's docstring, with `law` (and `law_params`, the
    defaults when none) on both contacts."""
    import stickslip as ss
    m = ss.Model()
    a = m.add_body(1.0, v0=0.5)
    b = m.add_body(2.0)
    m.add_spring(a, None, 50.0)
    m.add_spring(a, b, 80.0)
    m.add_force(b, ss.signal.step(0.3, 0.0, 4.0))
    m.add_contact(a, None, law, 9.81, surface_velocity=0.3, **law_params)
    m.add_contact(b, a, law, 5.0, **law_params)
    return m


def controls(method: str) -> dict[str, float]:
    """The controls a pair runs with: h for a fixed-step method, max_steps for an adaptive one."""
    import stickslip as ss
    return {"h": H} if "h" in ss.REGISTRY["method"][method]["controls"] else {"max_steps": MAX_STEPS}


def outcome(law: str, method: str) -> str:
    """How `method` ends on `general_model(law)`: "ok", "refused" or the error's class name."""
    import stickslip as ss
    model = general_model(law)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ss.simulate(model, method=method, t_end=T_END, n_out=11, **controls(method))
    except ValueError:
        return "refused"
    except ss.IntegrationError as err:
        return type(err).__name__
    return "ok"


def table() -> tuple[list[str], list[list[str]]]:
    """The CSV's header and rows: a row per law, a column per method."""
    import stickslip as ss
    header = ["law [-]"] + [f"{m} [-]" for m in ss.METHODS]
    return header, [[law] + [outcome(law, m) for m in ss.METHODS] for law in ss.LAWS]


def run(outdir: str | Path, *, quick: bool = False, threads: int = 1, quiet: bool = False) -> list[Path]:
    """Run every pair and write model_law_method.csv (quick and threads change nothing)."""
    header, rows = table()
    c.log(f"model_pairs: {len(rows)} laws x {len(header) - 1} methods", quiet)
    return [c.write_csv(Path(outdir) / "model_law_method.csv", header, rows)]


def main(argv: Sequence[str] | None = None) -> list[Path]:
    return c.study_main("cases.model_pairs", __doc__, "the same run (the table is small)", run, argv)


if __name__ == "__main__":
    main()
