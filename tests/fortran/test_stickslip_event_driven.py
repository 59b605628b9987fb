"""event_driven on every input (issue 41): normal forces that cross zero between the corners of
their signals, budgets and Ctrl-C honoured in every loop, failures that name the method and keep
the motion computed. Checked against a closed form (one body whose normal force crosses zero
twice between its table's points) and, on random models (2-8 bodies, coupled and redundant
contacts, normal forces that drop, cross zero and close again), against the independent
event-driven reference with exhaustive mode search of tests/contact_reference.py. The full
campaign (200 models) is marked slow; the default run takes a handful."""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import pytest
from scipy.optimize import brentq

import stickslip as ss
from stickslip import signal as S
from contact_reference import Reference


# ---------------------------------------------------------------------------------------------
# The example of issue 41: one body, spring 100 N/m to the ground, N = table([0, .3, .6],
# [10, -10, 10]) (zero at 0.15 s and 0.45 s, between the table's points), mu_s 0.5, mu_k 0.4,
# v0 = 0.5 m/s.

K_EX, M_EX, MU_S_EX, MU_K_EX, V0_EX = 100.0, 1.0, 0.5, 0.4, 0.5
TAB_T, TAB_V = (0.0, 0.3, 0.6), (10.0, -10.0, 10.0)


def example_model() -> ss.Model:
    m = ss.Model()
    b = m.add_body(M_EX, v0=V0_EX)
    m.add_spring(b, None, k=K_EX)
    m.add_contact(b, None, "coulomb", normal_force=S.table(TAB_T, TAB_V), mu_s=MU_S_EX, mu_k=MU_K_EX)
    return m


def exact_one_body(t_grid: np.ndarray, t_end: float) -> tuple[np.ndarray, np.ndarray, list[tuple[float, str]]]:
    """The example in closed form, phase by phase: on each piece where N(t) = n0 + n1 (t - t0)
    is linear and the mode fixed, x'' + w^2 x = c0 + c1 (t - t0) (slip: -s mu_k N / m; open,
    N <= 0: 0; stuck: x constant). Phase ends: the table's points, N = 0 (exact: linear), v = 0
    while slipping on a closed contact (brentq on the closed form), the static limit while
    stuck (exact: linear in t). At v = 0 the contact sticks when k |x| <= mu_s N, else slips
    towards -x; a contact that closes slips the way it moves."""
    w2 = K_EX / M_EX
    w = math.sqrt(w2)
    bps = sorted(set(TAB_T) | {0.15, 0.45, t_end})

    def normal(t: float) -> float:
        return max(float(np.interp(t, TAB_T, TAB_V)), 0.0)

    def raw_slope(t: float) -> tuple[float, float]:
        n0 = float(np.interp(t, TAB_T, TAB_V))
        n1 = float(np.interp(t + 1e-9, TAB_T, TAB_V) - n0) / 1e-9
        return n0, n1

    x, v, t = 0.0, V0_EX, 0.0
    mode = 1                        # +-1 slipping, 0 stuck
    pieces: list[tuple[float, float, float, float, float, float, int]] = []   # t0, t1, x0, v0, c0, c1, mode
    events: list[tuple[float, str]] = []
    while t < t_end - 1e-15:
        t1 = min(b for b in bps if b > t + 1e-15)
        n0, n1 = raw_slope(t)
        closed = n0 > 1e-12 or (abs(n0) <= 1e-12 and n1 > 0)
        if mode == 0:
            c0 = c1 = 0.0
        elif closed:
            c0, c1 = -mode * MU_K_EX * n0 / M_EX, -mode * MU_K_EX * n1 / M_EX
        else:
            c0 = c1 = 0.0
        a_ = x - c0 / w2
        b_ = (v - c1 / w2) / w

        def xv(tt: float, t0: float = t, c0: float = c0, c1: float = c1, a_: float = a_, b_: float = b_):
            tau = tt - t0
            return (c0 + c1 * tau) / w2 + a_ * math.cos(w * tau) + b_ * math.sin(w * tau), \
                c1 / w2 - a_ * w * math.sin(w * tau) + b_ * w * math.cos(w * tau)

        t_stop, why = t1, "piece"
        if mode == 0:
            # stuck: breakaway where mu_s N(t) = k |x| (N linear on the piece)
            if n1 < 0:
                tb = t + (K_EX * abs(x) / MU_S_EX - n0) / n1
                if t < tb < t1:
                    t_stop, why = tb, "slip"
        elif closed:
            grid = np.linspace(t, t1, 4001)
            vs = np.array([xv(g)[1] for g in grid]) * mode
            bad = np.flatnonzero(vs[1:] <= 0)
            if bad.size:
                j = bad[0] + 1
                t_stop, why = brentq(lambda tt: xv(tt)[1], grid[j - 1], grid[j], xtol=1e-15, rtol=1e-15), "v0"
        pieces.append((t, t_stop, x, v, c0, c1, mode))
        if mode == 0:
            xn, vn = x, 0.0
        else:
            xn, vn = xv(t_stop)
        t, x, v = t_stop, xn, vn
        if why == "v0":
            v = 0.0
            if K_EX * abs(x) <= MU_S_EX * normal(t):
                mode = 0
                events.append((t, "stick"))
            else:
                mode = -int(np.sign(x))
                events.append((t, "reversal"))
        elif why == "slip":
            mode = -int(np.sign(x))
            events.append((t, "slip"))
        elif mode != 0:
            n0, n1 = raw_slope(t)
            if n0 > 1e-12 or (abs(n0) <= 1e-12 and n1 > 0):
                mode = int(np.sign(v)) if v != 0 else mode       # closes: slips the way it moves
    xs, vs = np.empty_like(t_grid), np.empty_like(t_grid)
    for j, tt in enumerate(t_grid):
        t0, t1_, x0, v0, c0, c1, md = next(p for p in pieces if p[0] <= tt <= p[1] + 1e-15)
        if md == 0:
            xs[j], vs[j] = x0, 0.0
            continue
        a_ = x0 - c0 / w2
        b_ = (v0 - c1 / w2) / w
        tau = tt - t0
        xs[j] = (c0 + c1 * tau) / w2 + a_ * math.cos(w * tau) + b_ * math.sin(w * tau)
        vs[j] = c1 / w2 - a_ * w * math.sin(w * tau) + b_ * w * math.cos(w * tau)
    return xs, vs, events


def test_normal_force_crossing_zero_between_corners_matches_the_closed_form() -> None:
    t_end = 1.0
    res = ss.simulate(example_model(), method="event_driven", t_end=t_end, n_out=401, rtol=1e-10, atol=1e-12)
    assert res.stats["status"] == 0
    x_ex, v_ex, ev_ex = exact_one_body(res.t, t_end)
    # the contact opens at 0.15 s and closes at 0.45 s; in between the body oscillates freely
    # and its velocity changes sign, so the direction at closing matters (4.4e-3 m before)
    assert np.max(np.abs(res.x[0] - x_ex)) < 1e-8
    assert np.max(np.abs(res.v[0] - v_ex)) < 1e-7
    assert [e for _, e in ev_ex] == [str(k) for k in res.events["kind"]]
    assert np.allclose([t for t, _ in ev_ex], res.events["t"], atol=1e-9)


def test_the_example_matches_the_reference_too() -> None:
    """The same run against the independent reference (tables in solve_ivp's events)."""
    t_end = 1.0
    res = ss.simulate(example_model(), method="event_driven", t_end=t_end, n_out=201, rtol=1e-10, atol=1e-12)
    ref = Reference(m=[M_EX], k=[[K_EX]], h=[[1.0]], b=[0.0], n=[10.0], mu_s=[MU_S_EX], mu_k=[MU_K_EX],
                    normal_tables=[(TAB_T, TAB_V)])
    y_ref, _ = ref.run([0.0], [V0_EX], t_end, res.t)
    assert np.max(np.abs(res.x[0] - y_ref[0])) < 1e-7


# ---------------------------------------------------------------------------------------------
# Random models against the reference.

@dataclass
class Spec:
    """A random model: bodies, springs (a, b or None, k), contacts (a, b or None, N, table or
    None, surface velocity, mu_s, mu_k) and the initial state."""
    masses: list[float]
    springs: list[tuple[int, int | None, float]]
    contacts: list[tuple[int, int | None, float, tuple | None, float, float, float]]
    x0: list[float]
    v0: list[float]
    t_end: float
    notes: list[str] = field(default_factory=list)

    def model(self) -> ss.Model:
        m = ss.Model()
        for mass, x, v in zip(self.masses, self.x0, self.v0):
            m.add_body(mass, x0=x, v0=v)
        for a, b, k in self.springs:
            m.add_spring(a, b, k=k)
        for a, b, n, tab, sv, mu_s, mu_k in self.contacts:
            normal = n if tab is None else S.table(*tab)
            m.add_contact(a, b, "coulomb", normal_force=normal, surface_velocity=sv if b is None else 0.0,
                          mu_s=mu_s, mu_k=mu_k)
        return m

    def reference(self) -> Reference:
        nb = len(self.masses)
        kmat = np.zeros((nb, nb))
        for a, b, k in self.springs:
            kmat[a, a] += k
            if b is not None:
                kmat[b, b] += k
                kmat[a, b] -= k
                kmat[b, a] -= k
        h = np.zeros((len(self.contacts), nb))
        bvec = np.zeros(len(self.contacts))
        for i, (a, b, n, tab, sv, mu_s, mu_k) in enumerate(self.contacts):
            h[i, a] = 1.0
            if b is None:
                bvec[i] = -sv
            else:
                h[i, b] = -1.0
        return Reference(m=self.masses, k=kmat, h=h, b=bvec, n=[c[2] for c in self.contacts],
                         mu_s=[c[5] for c in self.contacts], mu_k=[c[6] for c in self.contacts],
                         normal_tables=[c[3] for c in self.contacts])


def random_spec(seed: int) -> Spec:
    """2-8 bodies on springs to the ground and to each other; a contact of each body with the
    ground (some on a belt), contacts between bodies (coupled), some split into two halves on
    the same row (redundant); normal forces constant or tables that drop, cross zero and close
    again between their points."""
    rng = np.random.default_rng(seed)
    nb = int(rng.integers(2, 9))
    masses = list(rng.uniform(0.5, 2.0, nb))
    springs: list[tuple[int, int | None, float]] = [(i, None, float(rng.uniform(20.0, 200.0))) for i in range(nb)]
    for _ in range(int(rng.integers(0, nb))):
        a, b = (int(i) for i in rng.choice(nb, 2, replace=False))
        springs.append((a, b, float(rng.uniform(10.0, 100.0))))
    t_end = 1.0
    notes = []

    def normal() -> tuple[float, tuple | None]:
        n = float(rng.uniform(2.0, 20.0))
        if rng.random() < 0.5:
            return n, None
        # a table that drops, crosses zero (or not) and closes again, its points off the zeros
        t1, t2, t3 = sorted(rng.uniform(0.05, 0.95, 3))
        low = float(rng.uniform(-1.0, 0.6)) * n
        return n, ((0.0, t1, t2, t3), (n, low, float(rng.uniform(-0.5, 1.0)) * n, n))

    contacts = []
    for i in range(nb):
        n, tab = normal()
        mu_k = float(rng.uniform(0.2, 0.5))
        mu_s = mu_k + float(rng.choice([0.0, rng.uniform(0.0, 0.2)]))
        sv = float(rng.choice([0.0, rng.uniform(-0.5, 0.5)]))
        contacts.append((i, None, n, tab, sv, mu_s, mu_k))
    for _ in range(int(rng.integers(1, nb))):
        a, b = (int(i) for i in rng.choice(nb, 2, replace=False))
        n, tab = normal()
        mu_k = float(rng.uniform(0.2, 0.5))
        mu_s = mu_k + float(rng.choice([0.0, rng.uniform(0.0, 0.2)]))
        contacts.append((a, b, n, tab, 0.0, mu_s, mu_k))
    if rng.random() < 0.3:
        # split a contact in two halves on the same row (redundant contacts)
        j = int(rng.integers(len(contacts)))
        a, b, n, tab, sv, mu_s, mu_k = contacts[j]
        half = None if tab is None else (tab[0], tuple(0.5 * v for v in tab[1]))
        contacts[j] = (a, b, 0.5 * n, half, sv, mu_s, mu_k)
        contacts.append((a, b, 0.5 * n, half, sv, mu_s, mu_k))
        notes.append("redundant")
    x0 = list(rng.uniform(-0.02, 0.02, nb))
    v0 = list(rng.uniform(-0.5, 0.5, nb))
    return Spec(masses, springs, contacts, x0, v0, t_end, notes)


MAX_STEPS = 200_000
MAX_EVENTS = 2_000


def check_against_reference(seed: int, seen: dict[str, list[int]] | None = None) -> str:
    """Run model `seed` with event_driven and the reference: "agree", "tie" (event_driven
    itself counted a decision with another solution, stats["nonunique"], at or before the time
    the runs part: the user was told), "halves" (below) or "failed" (a named failure within the
    budgets). A wrong motion with success fails the test. `seen` (if given) collects the seeds
    where the runs part at an instant the reference records as a tie ("ref tie"), whether or not
    event_driven flagged it: how many of the reference's ties event_driven reports."""
    spec = random_spec(seed)
    n_out = 101
    try:
        res = ss.simulate(spec.model(), method="event_driven", t_end=spec.t_end, n_out=n_out, rtol=1e-10,
                          atol=1e-12, max_steps=MAX_STEPS, max_events=MAX_EVENTS)
        failed = None
    except ss.IntegrationError as err:
        res, failed = err.result, err
        assert "event_driven" in str(err)
    nc = len(spec.contacts)
    assert res.stats["nstep"] <= MAX_STEPS, seed
    assert res.stats["nevents"] <= MAX_EVENTS + 4 * nc + 8, seed
    ref = spec.reference()
    t_grid = np.linspace(0.0, spec.t_end, n_out)
    try:
        y_ref, _ = ref.run(spec.x0, spec.v0, spec.t_end, t_grid, rtol=1e-11, atol=1e-13)
    except RuntimeError:
        return "reference stalled"      # the reference's own limit (no mode, or no progress)
    rows = n_out
    if failed is not None:
        # the motion up to where it stopped is kept, and agrees with the reference there
        reached = res.stats["t_reached"]
        rows = int(np.count_nonzero(t_grid <= reached))
        assert res.x.shape[1] >= rows
    err = np.abs(res.x[:, :rows] - y_ref[:len(spec.masses), :rows]).max(axis=0, initial=0.0)
    if np.all(err < 1e-6):
        return "failed" if failed is not None else "agree"
    j_part = int(np.argmax(err >= 1e-6))
    t_part = t_grid[j_part]
    if seen is not None:
        # the reference's own record: a tie where they part, after the last row where they
        # still agree to 1e-9 (the criterion of the campaign before event_driven counted ties)
        close = np.flatnonzero(err[:j_part] < 1e-9)
        t_from = t_grid[close[-1]] if close.size else 0.0
        if any(t_from - 1e-9 <= tt <= t_part + 1e-9 for tt in ref.ties):
            seen.setdefault("ref tie", []).append(seed)
    if flagged_by(spec, res, t_part):
        return "tie"
    if failed is None and "redundant" in spec.notes and merged_agrees(spec):
        # the same model with the two halves as one contact agrees: the contact solver's rule
        # counts the halves' stuck modes twice (issue 41, item 5; stickslip_contact_solver)
        return "halves"
    pytest.fail(f"model {seed}: event_driven {'failed' if failed else 'succeeded'} with a motion "
                f"{err.max():.3g} m from the reference (from t = {t_part:.4g} s; {len(spec.masses)} bodies, "
                f"{nc} contacts {spec.notes}) and no decision with another solution counted before")


def flagged_by(spec: Spec, res: ss.Result, t_part: float) -> bool:
    """Did event_driven count a decision with another solution (stats["nonunique"]) at or
    before t_part? The same run stopped at t_end = t_part (its rows up to there equal the full
    run's to 1e-9: the same decisions) says so by its count, which is what a user running to
    t_part is warned of."""
    if t_part <= 0.0:
        return False
    n = int(round(t_part / spec.t_end * (res.t.size - 1))) + 1
    try:
        part = ss.simulate(spec.model(), method="event_driven", t_end=t_part, n_out=n, rtol=1e-10, atol=1e-12,
                           max_steps=MAX_STEPS, max_events=MAX_EVENTS)
    except ss.IntegrationError as err:
        part = err.result
    rows = min(part.x.shape[1], res.x.shape[1], n, int(np.count_nonzero(part.t <= part.stats["t_reached"])))
    same = np.max(np.abs(part.x[:, :rows] - res.x[:, :rows]), initial=0.0) < 1e-9
    return bool(same and part.stats["nonunique"] > 0)


def merged_agrees(spec: Spec) -> bool:
    """Does event_driven agree with the reference on `spec` with its two halves (the last
    contact and its twin) made one contact again?"""
    last = spec.contacts[-1]
    j = spec.contacts.index(last)
    a, b, n, tab, sv, mu_s, mu_k = last
    whole = (a, b, 2.0 * n, None if tab is None else (tab[0], tuple(2.0 * v for v in tab[1])), sv, mu_s, mu_k)
    merged = Spec(spec.masses, spec.springs, spec.contacts[:j] + [whole] + spec.contacts[j + 1:-1], spec.x0,
                  spec.v0, spec.t_end)
    t_grid = np.linspace(0.0, spec.t_end, 101)
    try:
        res = ss.simulate(merged.model(), method="event_driven", t_end=spec.t_end, n_out=101, rtol=1e-10,
                          atol=1e-12, max_steps=MAX_STEPS, max_events=MAX_EVENTS)
    except ss.IntegrationError:
        return False
    try:
        y_ref, _ = merged.reference().run(merged.x0, merged.v0, merged.t_end, t_grid, rtol=1e-11, atol=1e-13)
    except RuntimeError:
        return False
    return bool(np.all(np.abs(res.x - y_ref[:len(spec.masses)]) < 1e-6))


@pytest.mark.parametrize("seed", [1, 2, 5, 9, 11, 14, 6, 1024, 1050, 1078])
def test_random_models_against_the_reference(seed: int) -> None:
    """A handful of the random models (6 and 1024 hold cycles of contacts, e.g. two bodies on
    the ground and on each other, whose stuck set has a singular Delassus block: they ended in
    a contact failure before psd_solve kept its right-hand side for the pseudo-solve; in 1050
    a contact closes on a row held by another at w = 0 to rounding, and is decided, not slipped
    on the sign of rounding; in 1078 a slipping contact's w comes back to 0 within one of the
    reference's steps)."""
    assert check_against_reference(seed) == "agree"


def _nonunique_and_warnings(model: ss.Model, t_end: float) -> tuple[int, list[str], float]:
    """event_driven's stats["nonunique"] on `model` up to t_end, its RuntimeWarnings about
    another solution, and stats["t_nonunique"] (the first one's time)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = ss.simulate(model, method="event_driven", t_end=t_end, n_out=2, rtol=1e-10, atol=1e-12)
    said = [str(w.message) for w in caught
            if issubclass(w.category, RuntimeWarning) and "another solution" in str(w.message)]
    return int(res.stats["nonunique"]), said, float(res.stats["t_nonunique"])


def test_a_closed_loop_let_go_by_its_forces_is_counted_and_warned_once() -> None:
    """Model 1113: bodies 1 and 2 each on the ground and on each other (contacts 1, 2 and the
    halves 7 and 10), a closed loop of stuck contacts whose holding forces are not unique. At
    0.12857 s the mode's minimum-norm forces take 7 and 10 to their limit and event_driven lets
    them go; contact 2 slipping instead, with 7 and 10 held, is another solution with as many
    stuck contacts, where the reference (exhaustive search) goes. The decision is counted
    (stats["nonunique"], the first one's time in stats["t_nonunique"]) and the run warns once,
    naming the count and that time; nothing before it is counted, and the reference records
    its tie between the two times too."""
    spec = random_spec(1113)
    before, said_before, _ = _nonunique_and_warnings(spec.model(), 0.1285)
    after, said, first = _nonunique_and_warnings(spec.model(), 0.1287)
    assert before == 0 and not said_before
    assert after >= 1 and 0.1285 < first <= 0.1287
    assert len(said) == 1 and f"{after} contact problem(s)" in said[0] and f"the first at t = {first:.6g} s" in said[0]
    ref = spec.reference()
    ref.run(spec.x0, spec.v0, 0.1287, np.array([0.0, 0.1287]), rtol=1e-11, atol=1e-13)
    assert any(0.1285 < t <= 0.1287 for t in ref.ties), ref.ties


def test_stacked_blocks_tie_at_rest_is_counted_and_a_unique_run_is_not() -> None:
    """The stacked blocks of issue 41 (base set) from rest: at t = 0 two mode sets with one stuck
    contact each are consistent (the reference records its tie at 0): event_driven's first
    decision counts one and warns once. The closed-form example (one contact) never has another
    solution: no count, no warning."""
    from test_stickslip_contact import STACKED_SETS, _stack, G
    friction = STACKED_SETS["base"]
    n, said, first = _nonunique_and_warnings(_stack(friction), 1e-6)
    assert n == 1 and first == 0.0 and len(said) == 1 and "1 contact problem(s)" in said[0]
    assert "the first at t = 0 s" in said[0]
    ref = Reference(m=[2.0, 1.0, 0.5], k=np.diag([200.0, 60.0, 30.0]), h=[[1, 0, 0], [-1, 1, 0], [0, -1, 1]],
                    b=[-0.3, 0.0, 0.0], n=[3.5 * G, 1.5 * G, 0.5 * G], mu_s=[f[0] for f in friction],
                    mu_k=[f[1] for f in friction])
    ref.run([0.0] * 3, [0.0] * 3, 1e-6, np.array([0.0, 1e-6]))
    assert 0.0 in ref.ties
    assert _nonunique_and_warnings(example_model(), 1.0) == (0, [], 0.0)


def test_a_slip_from_the_limit_at_zero_acceleration_is_counted_where_a_strict_mode_exists() -> None:
    """Model 1136: contacts 1, 3 and 6 (0-based) form a closed loop of stuck contacts; at
    0.149122 s contact 1, with mu_s = mu_k, reaches its limit. event_driven lets it alone slip,
    the mode with the most stuck contacts, whose slip starts with zero relative acceleration
    (consistent to first order only); the reference lets 1 and 6 slip at that instant, a mode
    with one stuck contact less that holds strictly. Which continuation is right depends on
    higher derivatives: the decision is counted and warned once, and nothing before it. Both
    continuations hold beyond first order (event_driven's slipping contact stays at w = 0, held
    by the loop; the reference's two move)."""
    spec = random_spec(1136)
    before, said_before, _ = _nonunique_and_warnings(spec.model(), 0.14912)
    after, said, first = _nonunique_and_warnings(spec.model(), 0.14913)
    assert before == 0 and not said_before
    assert after == 1 and 0.14912 < first <= 0.14913 and len(said) == 1 and "first order" in said[0]
    res = ss.simulate(spec.model(), method="event_driven", t_end=0.14913, n_out=2, rtol=1e-10, atol=1e-12)
    mine = [(int(e["contact"]), str(e["kind"])) for e in res.events if e["t"] > 0.14912]
    _, ref_events = spec.reference().run(spec.x0, spec.v0, 0.14913, np.array([0.0, 0.14913]), rtol=1e-11,
                                         atol=1e-13)
    theirs = sorted(int(i) for t, i, _ in ref_events if t > 0.14912)
    assert mine == [(1, "slip")]
    assert theirs == [1, 6]
    # two continuations, not one wrong: 1 ms on, event_driven's contact 1 (slipping, its row a
    # combination of 3's and 6's, which hold) still has w = 0 to rounding, its force at its
    # limit, a motion consistent beyond first order; in the reference's 1 and 6 move

    def w_of(v: np.ndarray, i: int) -> float:
        a, b, _, _, sv, _, _ = spec.contacts[i]
        return float(v[a] - (v[b] if b is not None else sv))

    t1 = 0.15012
    v_ed = ss.simulate(spec.model(), method="event_driven", t_end=t1, n_out=2, rtol=1e-10, atol=1e-12).v[:, -1]
    y_ref, _ = spec.reference().run(spec.x0, spec.v0, t1, np.array([0.0, t1]), rtol=1e-11, atol=1e-13)
    v_ref = y_ref[len(spec.masses):, -1]
    assert max(abs(w_of(v_ed, 1)), abs(w_of(v_ed, 6))) < 1e-12
    assert min(abs(w_of(v_ref, 1)), abs(w_of(v_ref, 6))) > 1e-6


def test_a_break_away_at_mu_s_equal_mu_k_with_no_other_mode_is_not_counted() -> None:
    """B on A, A on a belt (0.2 m/s) with a spring to the wall: both stuck, A's ground contact
    (mu_s = mu_k = 0.3, N = 20 N) reaches its limit at t = mu N / (k v) = 0.3 s and slips with
    zero relative acceleration (consistent to first order only, as in 1136), but B slipping on A
    too is not consistent (B, pulled by its friction alone, would accelerate against its slip):
    no other mode, nothing counted, and the motion is the reference's."""
    spec = Spec(masses=[1.0, 1.0], springs=[(0, None, 100.0)],
                contacts=[(0, None, 20.0, None, 0.2, 0.3, 0.3), (1, 0, 10.0, None, 0.0, 0.5, 0.5)],
                x0=[0.0, 0.0], v0=[0.2, 0.2], t_end=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        res = ss.simulate(spec.model(), method="event_driven", t_end=1.0, n_out=101, rtol=1e-10, atol=1e-12)
    assert res.stats["nonunique"] == 0
    first = res.events[0]
    assert (int(first["contact"]), str(first["kind"])) == (0, "slip")
    assert abs(first["t"] - 0.3 * 20.0 / (100.0 * 0.2)) < 1e-9
    y_ref, _ = spec.reference().run(spec.x0, spec.v0, 1.0, np.linspace(0.0, 1.0, 101), rtol=1e-11, atol=1e-13)
    assert np.max(np.abs(res.x - y_ref[:2])) < 1e-6


#: The campaign's models on which event_driven still ends in success with another motion than
#: the reference's, or fails after rows that differ from it, with no decision with another
#: solution counted before they part: the open part of the work on event_driven's inputs, each
#: with what was seen. A list that may only shrink: a model that agrees again fails the test
#: until it is removed here. (1072 and 1113 left it when event_driven counted the decisions where
#: a closed loop of stuck contacts lets a contact go that another holding, or another stuck set,
#: would keep: both part from the reference after such a decision, at 0.1094 s and 0.12857 s,
#: instants the reference records as ties too; 1124 when the contact solver's test at rest also
#: tried a held contact with the neighbours it overloads slipping; 1117 and 1136 when it counted a
#: decision consistent to first order only: a contact of a closed loop with mu_s = mu_k let slip
#: from its limit at zero relative acceleration, where the reference's mode, with a second
#: contact slipping, holds strictly.)
KNOWN_WRONG: dict[int, str] = {}


@pytest.mark.slow
def test_random_campaign_of_200_models() -> None:
    """200 random models: none may end in success with a motion other than the reference's
    unless event_driven itself counted a decision with another solution before they part
    ("tie": the run warned; and the two-halves rule of the contact solver, counted apart), but
    the listed ones (KNOWN_WRONG); every run within its budgets. The outcome counts are printed,
    with the runs that part where the reference records a tie ("ref tie") and how many of those
    event_driven flagged."""
    outcome: dict[str, list[int]] = {"agree": [], "tie": [], "halves": [], "failed": [],
                                     "reference stalled": [], "wrong": []}
    seen: dict[str, list[int]] = {}
    wrong = []
    for seed in range(1000, 1200):
        try:
            outcome[check_against_reference(seed, seen)].append(seed)
        except (pytest.fail.Exception, AssertionError) as err:
            outcome["wrong"].append(seed)
            if seed not in KNOWN_WRONG:
                wrong.append(f"model {seed}: {err}")
    ref_tie = seen.get("ref tie", [])
    print({k: len(v) for k, v in outcome.items()}, {k: v for k, v in outcome.items() if k != "agree"})
    print(f"parted at a tie the reference records: {len(ref_tie)} {ref_tie}; of these flagged by event_driven: "
          f"{len(set(ref_tie) & set(outcome['tie']))}")
    assert not wrong, "\n".join(wrong)
    stale = sorted(set(KNOWN_WRONG) - set(outcome["wrong"]))
    assert not stale, f"models {stale} no longer go wrong: remove them from KNOWN_WRONG"


# ---------------------------------------------------------------------------------------------
# Budgets, failures and the partial motion.

def test_event_budget_names_the_method_and_keeps_the_motion() -> None:
    with pytest.raises(ss.EventBudgetExhausted) as info:
        ss.simulate(example_model(), method="event_driven", t_end=3.0, n_out=301, max_events=1)
    res = info.value.result
    assert "event_driven" in str(info.value)
    assert 0.0 < res.stats["t_reached"] < 3.0
    x_ex, _, _ = exact_one_body(res.t, 3.0)
    done = res.t <= res.stats["t_reached"]
    assert done.sum() >= 2
    assert np.max(np.abs(res.x[0, done] - x_ex[done])) < 1e-5


def test_step_budget_is_honoured_with_events_in_every_mode() -> None:
    """max_steps counts the steps of every mode's run: the run stops at the budget, keeps what
    it computed, and says so (before, a run past its budget went on one step per mode)."""
    for budget in (1, 5, 40):
        with pytest.raises(ss.StepBudgetExhausted) as info:
            ss.simulate(example_model(), method="event_driven", t_end=3.0, n_out=31, max_steps=budget)
        res = info.value.result
        assert "event_driven" in str(info.value)
        assert res.stats["nstep"] <= budget


def test_ctrl_c_stops_a_run_of_many_short_modes() -> None:
    """SIGINT half a second into a stick-slip run of about a million events (a minute or more):
    KeyboardInterrupt, not the end of the run (the stop flag is looked at before every mode's
    run, each of a few steps)."""
    import subprocess
    import sys
    code = ("import os, signal, threading\n"
            "import stickslip as ss\n"
            "m = ss.Model()\n"
            "b = m.add_body(1.0)\n"
            "m.add_spring(b, None, k=100.0)\n"
            "m.add_contact(b, None, 'coulomb', normal_force=10.0, surface_velocity=0.3, mu_s=0.5, mu_k=0.3)\n"
            "threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()\n"
            "try:\n"
            "    ss.simulate(m, method='event_driven', t_end=1e6, n_out=2, max_events=10**8)\n"
            "    print('finished')\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted')\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
    assert proc.stdout.split() == ["interrupted"], proc.stdout + proc.stderr
