"""Friction in physics engines, as laws stickslip can state exactly.

Five engine models regularise Coulomb friction by a law of the slip speed alone, and the steady
creep of the paper's slope box (10 kg, 10 degrees, mu_s = 0.35, mu_k = 0.30, which truly never
moves) in each follows from the balance of that law on the slope, mu(v*) N = m g sin(theta):

- ``drake_continuous``: Drake's MultibodyPlant in continuous mode (point contact), its
  StribeckModel: mu_s step5(v / v_s) below the stiction tolerance v_s, a quintic step down to
  mu_d on [v_s, 3 v_s], mu_d beyond; step5(x) = 10 x^3 - 15 x^4 + 6 x^5 (the paper's haversine
  family: a C2 step instead of a half cosine). Source: drake, multibody/plant/multibody_plant.cc,
  ``StribeckModel::ComputeFrictionCoefficient`` and ``step5`` (drake 1.x; the law is unchanged
  since 2019).
- ``drake_tamsi``: Drake's discrete MultibodyPlant with the TAMSI solver: mu s (2 - s) for
  s = v / v_s < 1, mu beyond, with mu the dynamic coefficient (discrete Drake ignores the static
  one). Source: drake, ``StribeckModel::ModifiedStribeck`` (multibody_plant.cc, drake 1.x);
  checked against drake 1.51.1's own runs.
- ``drake_lagged``: Drake's default discrete model (the "lagged" convex approximation of
  compliant contact): friction regularised by the stiction tolerance (Drake's
  ``DiscreteContactApproximation`` documentation, drake 1.51; Castro, Han and Masterjohn 2023),
  of the form mu_d s / sqrt(1 + s^2), s = v / v_s. The form is identified from Drake's own runs,
  not read from its source: their creep is proportional to v_s and v* / v_s = 0.7265, the root
  of mu_d s / sqrt(1 + s^2) = tan(theta) (python -m cases.engines); on slopes of 5 and 15
  degrees the same form predicts Drake's creep to 1e-7 (tests/test_engines.py).
- ``mujoco``: MuJoCo's soft contact. Inside the friction cone each frictional constraint row
  gives the force D (a_ref - a) with D = 1 / R and a_ref = -B v (K = 0 in friction rows), so at a
  steady slip (a = 0) the contact acts as a viscous damper of coefficient B / R_friction:
  B = 2 / (d_max t_c) (t_c = max(solref[0], 2 timestep), or -solref[1] / d_max in the direct
  format); R_0 = (1 - d) / d * A with d the impedance at the contact's penetration (solimp) and A
  the body's translational inverse weight (1 / m for a free box); elliptic cone: R_friction =
  R_0 / impratio; pyramidal cone: each of the four edge rows n +- mu t has A = (1 + mu^2) / m and
  R = 2 (mu^2 / impratio) R_0, and an edge whose force would be negative drops out. Source:
  mujoco, src/engine/engine_core_constraint.c (``mj_diagApprox``, ``mj_makeImpedance``,
  ``getimpedance``; mujoco 3.x); checked against mujoco 4.0.0's own runs to 1e-7.
- ``newton_semi_implicit``: Newton's (and warp.sim's) semi-implicit Euler rigid contact:
  min(k_f |v_t|, mu f_n) per contact point, k_f the mean of the two shapes' (default 1000
  N s/m, ``ModelBuilder.ShapeConfig.kf``). Source: newton 1.8,
  newton/_src/solvers/semi_implicit/kernels_contact.py (``eval_body_contact``), and warp.sim's
  ``eval_rigid_contacts``.

Bullet's sequential-impulse solver and Drake's SAP solver (whose regularisation Drake sets
from the numerics alone) have no smooth law of this kind: they solve a velocity-level cone
problem each step, and what creep they show is measured by ``python -m cases.engines``, not
predicted here (`NO_LAW`).

`engine_creep` returns the creep speed, `advise_engine` the setting for a creep budget,
`engine_mu` the equivalent friction coefficient of the whole box at a slip speed.
"""
from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np

#: The engines with an equivalent law, each with its settings and their defaults (the engine's
#: own defaults; mu None: the scene's mu_k).
ENGINE_SETTINGS: dict[str, dict[str, Any]] = {
    "drake_continuous": {"stiction_tolerance": 1e-4},
    "drake_tamsi": {"stiction_tolerance": 1e-4},
    "drake_lagged": {"stiction_tolerance": 1e-4},
    "mujoco": {"cone": "pyramidal", "impratio": 1.0, "solref": (0.02, 1.0),
               "solimp": (0.9, 0.95, 0.001, 0.5, 2.0), "timestep": 0.002, "n_contacts": 4,
               "mu": None},
    "newton_semi_implicit": {"k_f": 1000.0, "n_contacts": 4, "mu": None},
}
#: The engines with an equivalent law (engine_creep, advise_engine and engine_mu take them).
ENGINES: tuple[str, ...] = tuple(ENGINE_SETTINGS)
#: Engines without a smooth law, and why.
NO_LAW: dict[str, str] = {
    "bullet": "Bullet solves a velocity-level friction cone by sequential impulses each step: no "
              "smooth law; its creep is measured (python -m cases.engines)",
    "drake_sap": "Drake's SAP solver solves a convex velocity-level cone problem each step: no "
                 "smooth law; its creep is measured",
}
#: The slope's parameters (the paper's) and the engines' box: aspect = height of the centre of
#: mass above the contact plane over the half-length of the footprint along the slope (0.5: a
#: 0.2 x 0.2 x 0.1 m box); it sets how the normal load splits between the front and back
#: contacts of a 4-contact box.
SCENE_DEFAULTS: dict[str, float] = {"theta_deg": 10.0, "m": 10.0, "g": 9.81, "mu_s": 0.35,
                                    "mu_k": 0.30, "aspect": 0.5}
CONES: tuple[str, ...] = ("pyramidal", "elliptic")


def _names(seq: Any) -> str:
    return ", ".join(seq)


def _split(engine: str, settings: dict[str, Any]) -> tuple[dict[str, float], dict[str, Any]]:
    """Check the engine and its settings; return (scene, engine settings) with defaults."""
    if engine in NO_LAW:
        raise ValueError(f"{engine}: {NO_LAW[engine]}; engines with a law: {_names(ENGINES)}")
    if engine not in ENGINE_SETTINGS:
        raise ValueError(f"unknown engine {engine!r}; accepted: {_names(ENGINES)}")
    scene, own = dict(SCENE_DEFAULTS), dict(ENGINE_SETTINGS[engine])
    for key, value in settings.items():
        if key in SCENE_DEFAULTS:
            scene[key] = float(value)
        elif key in own:
            own[key] = value
        else:
            raise ValueError(f"{engine} has no setting {key!r}; accepted: "
                             f"{_names(list(own) + list(SCENE_DEFAULTS))}")
    for key in ("m", "g", "mu_s", "mu_k"):
        if not scene[key] > 0:
            raise ValueError(f"{key} must be > 0, got {scene[key]}")
    if not 0 < scene["theta_deg"] < 90:
        raise ValueError(f"theta_deg must be in (0, 90), got {scene['theta_deg']}")
    if not scene["aspect"] >= 0:
        raise ValueError(f"aspect must be >= 0, got {scene['aspect']}")
    for key, value in own.items():
        if value is None and key != "mu":
            raise ValueError(f"{engine} needs the setting {key!r} (no default)")
    if "mu" in own and own["mu"] is None:
        own["mu"] = scene["mu_k"]        # one coefficient: the kinetic one
    for key in ("stiction_tolerance", "impratio", "timestep", "k_f", "mu"):
        if key in own and not float(own[key]) > 0:
            raise ValueError(f"{key} must be > 0, got {own[key]}")
    if "n_contacts" in own:
        n = own["n_contacts"]
        if isinstance(n, bool) or int(n) != n or n < 1:
            raise ValueError(f"n_contacts must be an integer >= 1, got {n}")
        own["n_contacts"] = int(n)
    if "cone" in own and own["cone"] not in CONES:
        raise ValueError(f"unknown cone {own['cone']!r}; accepted: {_names(CONES)}")
    if "solref" in own:
        ref = tuple(float(x) for x in own["solref"])
        if len(ref) != 2 or (ref[0] > 0) != (ref[1] > 0) or 0 in ref:
            raise ValueError(f"solref must be (timeconst > 0, dampratio > 0) or (-stiffness, "
                             f"-damping), got {own['solref']}")
        own["solref"] = ref
    if "solimp" in own:
        imp = tuple(float(x) for x in own["solimp"])
        if len(imp) != 5 or not (0 < imp[0] < 1 and 0 < imp[1] < 1 and imp[2] >= 0
                                 and 0 < imp[3] < 1 and imp[4] >= 1):
            raise ValueError(f"solimp must be (dmin, dmax in (0, 1), width >= 0, midpoint in "
                             f"(0, 1), power >= 1), got {own['solimp']}")
        own["solimp"] = imp
    return scene, own


# ------------------------------------------------------------------------------------------
# The laws
# ------------------------------------------------------------------------------------------
def step5(x: Any) -> np.ndarray:
    """Drake's quintic step 10 x^3 - 15 x^4 + 6 x^5 on [0, 1] (0 below, 1 above)."""
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return x ** 3 * (10.0 + x * (6.0 * x - 15.0))


def drake_continuous_mu(v: Any, stiction_tolerance: float, mu_s: float, mu_d: float) -> np.ndarray:
    """Drake's continuous-mode friction coefficient at slip speed |v| [m/s] (even in v)."""
    s = np.abs(np.asarray(v, dtype=float)) / stiction_tolerance
    return np.where(s >= 3, mu_d, np.where(s >= 1, mu_s - (mu_s - mu_d) * step5((s - 1) / 2),
                                           mu_s * step5(s)))


def drake_tamsi_mu(v: Any, stiction_tolerance: float, mu: float) -> np.ndarray:
    """TAMSI's regularised coefficient mu s (2 - s), s = |v| / v_s < 1, else mu."""
    s = np.minimum(np.abs(np.asarray(v, dtype=float)) / stiction_tolerance, 1.0)
    return mu * s * (2.0 - s)


def drake_lagged_mu(v: Any, stiction_tolerance: float, mu: float) -> np.ndarray:
    """Drake's lagged approximation's regularised coefficient mu s / sqrt(1 + s^2), s = |v| / v_s
    (identified from Drake's runs; see the module's documentation)."""
    s = np.abs(np.asarray(v, dtype=float)) / stiction_tolerance
    return mu * s / np.sqrt(1.0 + s * s)


def mujoco_impedance(solimp: tuple[float, ...], depth: float) -> float:
    """MuJoCo's impedance d at a penetration depth [m] (>= 0; zero margin), from solimp."""
    dmin, dmax, width, mid, power = solimp
    if dmin == dmax or width <= 1e-15:
        return 0.5 * (dmin + dmax)
    x = depth / width
    if x >= 1 or x <= 0:
        return dmax if x >= 1 else dmin
    if power == 1:
        y = x
    elif x <= mid:
        y = x ** power / mid ** (power - 1)
    else:
        y = 1 - (1 - x) ** power / (1 - mid) ** (power - 1)
    return dmin + y * (dmax - dmin)


def _mujoco_kb(own: dict[str, Any]) -> tuple[float, float]:
    """MuJoCo's K [1/s^2] and B [1/s] of solref (refsafe: timeconst >= 2 timestep)."""
    ref, dmax = own["solref"], own["solimp"][1]
    if ref[0] > 0:
        tc = max(ref[0], 2 * float(own["timestep"]))
        return 1 / (dmax ** 2 * tc ** 2 * ref[1] ** 2), 2 / (dmax * tc)
    return -ref[0] / dmax ** 2, -ref[1] / dmax


def _mujoco_contact(own: dict[str, Any], inv_weight: float, load: float,
                    v: float) -> tuple[float, float]:
    """One MuJoCo contact carrying the normal load [N] at slip speed v [m/s] (steady, zero
    acceleration): (tangential force [N], impedance d). The penetration follows from the
    normal balance, solved by bisection (the load grows with depth)."""
    K, B = _mujoco_kb(own)
    mu, ir, pyramidal = float(own["mu"]), float(own["impratio"]), own["cone"] == "pyramidal"

    def rows(depth: float) -> tuple[float, float, float]:
        d = mujoco_impedance(own["solimp"], depth)
        if pyramidal:
            r = 2 * (mu * mu / ir) * (1 - d) / d * (1 + mu * mu) * inv_weight
            p, q = K * d * depth / r, B * mu * v / r       # edge force = p -+ q (before clamping)
            if q <= p:
                return 4 * p, 2 * mu * q, d                 # four edges active
            return 3 * p + q, mu * (p + q), d               # the opposing edge drops out
        r0 = (1 - d) / d * inv_weight
        return K * d * depth / r0, B * v * ir / r0, d

    lo, hi = 0.0, 1e-6
    while rows(hi)[0] < load:
        lo, hi = hi, hi * 2
        if hi > 1e3:
            raise ValueError("MuJoCo contact: no penetration carries the load")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if rows(mid)[0] < load:
            lo = mid
        else:
            hi = mid
    _, t, d = rows(hi)
    return t, d


def _loads(scene: dict[str, float], n: int) -> list[float]:
    """Normal load [N] on each of n contacts: a 4-contact box's front and back pairs share the
    overturning moment of the friction (aspect), other counts share equally."""
    th = math.radians(scene["theta_deg"])
    total = scene["m"] * scene["g"] * math.cos(th)
    if n != 4:
        return [total / n] * n
    e = scene["aspect"] * math.tan(th)
    if e >= 1:
        raise ValueError(f"aspect {scene['aspect']} tips the box over on this slope")
    return [total / 4 * (1 + e)] * 2 + [total / 4 * (1 - e)] * 2


def _tangential(engine: str, scene: dict[str, float],
                own: dict[str, Any]) -> Callable[[float], float]:
    """Total friction force [N] on the box at slip speed v [m/s], by the engine's law."""
    N = scene["m"] * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    if engine == "drake_continuous":
        return lambda v: float(drake_continuous_mu(v, own["stiction_tolerance"], scene["mu_s"],
                                                   scene["mu_k"])) * N
    if engine == "drake_tamsi":
        return lambda v: float(drake_tamsi_mu(v, own["stiction_tolerance"], scene["mu_k"])) * N
    if engine == "drake_lagged":
        return lambda v: float(drake_lagged_mu(v, own["stiction_tolerance"], scene["mu_k"])) * N
    loads = _loads(scene, own["n_contacts"])
    if engine == "newton_semi_implicit":
        return lambda v: sum(min(own["k_f"] * v, own["mu"] * f) for f in loads)
    w = 1.0 / scene["m"]           # a free body's translational inverse weight (body_invweight0)
    return lambda v: sum(min(_mujoco_contact(own, w, f, v)[0], own["mu"] * f) for f in loads)


def engine_mu(engine: str, v: Any, **settings: Any) -> np.ndarray:
    """The engine's equivalent friction coefficient of the slope box at slip speed v [m/s]:
    its total friction force over the total normal load m g cos(theta).

    Parameters
    ----------
    engine : str
        One of `ENGINES`.
    v : float or array
        Slip speed [m/s] (>= 0).
    **settings
        The engine's settings (`ENGINE_SETTINGS`) and the scene's (`SCENE_DEFAULTS`).

    Returns
    -------
    numpy.ndarray
        mu(v) [-], the shape of v.
    """
    scene, own = _split(engine, settings)
    force = _tangential(engine, scene, own)
    N = scene["m"] * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    v = np.asarray(v, dtype=float)
    if np.any(~(v >= 0)):
        raise ValueError("v must be >= 0 (a slip speed)")
    return np.vectorize(lambda x: force(float(x)) / N)(v)


def engine_creep(engine: str, **settings: Any) -> float:
    """Steady creep speed [m/s] of the paper's slope box in a physics engine.

    The speed v* where the engine's friction law balances the slope, F(v*) = m g sin(theta),
    F being the total friction force of the box's contacts: in closed form for the Drake
    laws and Newton, by bisection on MuJoCo's contact rows (their penetration and impedance
    follow from the normal balance). math.inf when the law cannot hold the box at any speed
    (the box accelerates).

    Parameters
    ----------
    engine : str
        "drake_continuous", "drake_tamsi", "drake_lagged", "mujoco" or "newton_semi_implicit".
    **settings
        The engine's settings: stiction_tolerance [m/s] (Drake); cone ("pyramidal" or
        "elliptic"), impratio, solref, solimp, timestep [s], n_contacts, mu (MuJoCo); k_f
        [N s/m], n_contacts, mu (Newton); and the scene's: theta_deg, m [kg], g [m/s^2], mu_s,
        mu_k, aspect. Engines with one friction coefficient take mu = mu_k unless given.

    Returns
    -------
    float
        v* [m/s].

    Raises
    ------
    ValueError
        An unknown engine or setting, a setting the engine does not have, or a bad value.

    Examples
    --------
    >>> import stickslip as ss
    >>> round(ss.engine_creep("drake_tamsi", stiction_tolerance=1e-4) * 20 * 1e3, 3)  # mm in 20 s
    0.716
    """
    scene, own = _split(engine, settings)
    th = math.radians(scene["theta_deg"])
    pull = scene["m"] * scene["g"] * math.sin(th)
    t = math.tan(th)
    if engine == "drake_continuous":
        if t >= scene["mu_s"]:
            return math.inf
        target = t / scene["mu_s"]
        lo, hi = 0.0, 1.0                     # step5 is increasing on [0, 1]
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if float(step5(mid)) < target else (lo, mid)
        return 0.5 * (lo + hi) * own["stiction_tolerance"]
    if engine == "drake_tamsi":
        if t >= scene["mu_k"]:
            return math.inf
        return (1 - math.sqrt(1 - t / scene["mu_k"])) * own["stiction_tolerance"]
    if engine == "drake_lagged":
        if t >= scene["mu_k"]:
            return math.inf
        return t / math.sqrt(scene["mu_k"] ** 2 - t * t) * own["stiction_tolerance"]
    if t >= own["mu"]:
        return math.inf
    if engine == "newton_semi_implicit":
        loads = _loads(scene, own["n_contacts"])
        force = _tangential(engine, scene, own)
        # piecewise linear: below every cap F = n k_f v
        v = pull / (own["n_contacts"] * own["k_f"])
        if all(own["k_f"] * v <= own["mu"] * f for f in loads):
            return v
        return _bisect(force, pull)
    return _bisect(_tangential(engine, scene, own), pull)


def _bisect(force: Callable[[float], float], pull: float) -> float:
    """The speed where the increasing force(v) reaches pull."""
    lo, hi = 0.0, 1e-9
    while force(hi) < pull:
        lo, hi = hi, hi * 2
        if hi > 1e6:
            return math.inf
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if force(mid) < pull else (lo, mid)
    return 0.5 * (lo + hi)


#: The setting advise_engine chooses per engine.
ADVISED_SETTING: dict[str, str] = {"drake_continuous": "stiction_tolerance",
                                   "drake_tamsi": "stiction_tolerance",
                                   "drake_lagged": "stiction_tolerance", "mujoco": "impratio",
                                   "newton_semi_implicit": "k_f"}


def advise_engine(engine: str, max_creep: float, t_end: float, **settings: Any) -> dict[str, Any]:
    """Settings that keep the slope box's creep over t_end within max_creep.

    The advised setting (`ADVISED_SETTING`: Drake's stiction tolerance, MuJoCo's impratio for
    the given cone, Newton's k_f) is the loosest whose creep v* t_end meets the budget, rounded
    to 3 significant digits toward the strict side: never more than 2x stricter than needed.

    Parameters
    ----------
    engine : str
        One of `ENGINES`.
    max_creep : float
        Largest distance the box may creep [m] (> 0).
    t_end : float
        Duration [s] (> 0).
    **settings
        The engine's other settings and the scene's, as for `engine_creep` (not the advised
        one).

    Returns
    -------
    dict
        The advised setting by name, "creep" (v* t_end [m] at it), "v_star" [m/s], and where
        it is known the cost: "timestep" [s] and "steps_per_second" [1/s] (MuJoCo: its
        timestep; Drake continuous and Newton: the largest explicit (forward or semi-implicit
        Euler) step that is stable on the law's steepest slope dF/dv in the box's stiffest
        mode, its yaw on four corner contacts, 2 m / (3 dF/dv)); None where no cost is known
        (TAMSI, lagged).

    Raises
    ------
    ValueError
        An unknown engine or setting, the advised setting given, max_creep or t_end <= 0.
    """
    if engine in ENGINE_SETTINGS and ADVISED_SETTING[engine] in settings:
        raise ValueError(f"advise_engine chooses {ADVISED_SETTING[engine]} for {engine}; "
                         f"do not pass it")
    if not (isinstance(max_creep, (int, float)) and max_creep > 0 and math.isfinite(max_creep)):
        raise ValueError(f"max_creep must be a finite number > 0 [m], got {max_creep!r}")
    if not (isinstance(t_end, (int, float)) and t_end > 0 and math.isfinite(t_end)):
        raise ValueError(f"t_end must be a finite number > 0 [s], got {t_end!r}")
    scene, _ = _split(engine, settings)
    name = ADVISED_SETTING[engine]
    target = max_creep / t_end

    def creep(x: float) -> float:
        return engine_creep(engine, **settings, **{name: x})

    if engine.startswith("drake"):                            # v* proportional to v_s
        if not math.isfinite(creep(1.0)):
            raise ValueError(f"{engine} cannot hold the box on this slope at any {name}")
        value = target / creep(1.0)
    else:
        # creep decreases with impratio / k_f, nearly as 1 / x: start from that guess, then
        # bisection in log space on a bracket around it
        if not math.isfinite(creep(1e12)):
            raise ValueError(f"{engine} cannot hold the box on this slope at any {name}")
        guess = creep(1.0) / target
        lo, hi = guess / 1.5, guess * 1.5
        while creep(lo) <= target and lo > 1e-15:
            lo /= 2
        while creep(hi) > target:
            lo, hi = hi, hi * 2
            if hi > 1e15:
                raise ValueError(f"{engine}: no {name} up to 1e15 meets the budget")
        for _ in range(30):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if creep(mid) > target else (lo, mid)
        value = hi
    # 3 significant digits, rounded toward the strict side
    digits = 10 ** (math.floor(math.log10(value)) - 2)
    steps = math.floor(value / digits) if engine.startswith("drake") else math.ceil(value / digits)
    value = float(f"{steps * digits:.3g}")
    v_star = creep(value)
    out: dict[str, Any] = {name: value, "creep": v_star * t_end, "v_star": v_star,
                           "timestep": None, "steps_per_second": None}
    _, own = _split(engine, {**settings, name: value})
    m = scene["m"]
    N = m * scene["g"] * math.cos(math.radians(scene["theta_deg"]))
    # the stiffest mode of friction on a box with four corner contacts is its yaw: a uniform box
    # (I_z = m (hx^2 + hy^2) / 3) feels 3 dF/dv / m there, three times the translation's
    yaw = 3.0
    if engine == "mujoco":
        out["timestep"] = float(own["timestep"])
    elif engine == "drake_continuous":
        slope = scene["mu_s"] * 1.875 * N / value          # max of step5' is 15/8 at x = 1/2
        out["timestep"] = 2 * m / (yaw * slope)
    elif engine == "newton_semi_implicit":
        factor = yaw if own["n_contacts"] == 4 else 1.0
        out["timestep"] = 2 * m / (factor * own["n_contacts"] * value)
    if out["timestep"] is not None:
        out["steps_per_second"] = 1.0 / out["timestep"]
    return out
