"""Your own system: bodies, springs, dampers, forces, time signals and friction contacts.

`Model` collects and checks the elements; the library (Fortran modules
``stickslip_model_system`` and ``stickslip_user_model``) assembles and runs them with any
method, through `stickslip.simulate`. Bodies move on one axis each (a position in m, or an
angle in rad for an inertia); index None is the ground.

Examples
--------
>>> import stickslip as ss
>>> m = ss.Model()
>>> j1 = m.add_body(1.0, v0=1.0, name="J1")
>>> m.add_spring(j1, None, k=100.0)
>>> m.add_contact(j1, None, "coulomb", normal_force=9.81, mu_s=0.3, mu_k=0.3)
>>> res = ss.simulate(m, method="event_driven", t_end=1.0, n_out=3)
>>> res.x.shape
(1, 3)
"""
from __future__ import annotations

import math
import os
import struct
import tomllib
import warnings
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from . import _stickslip as _ext
from .core import (CONTROL_DEFAULTS, LAWS, METHODS, REGISTRY, STATUS_OK, Result,
                   _FIRST_INPUT_CODE, _choice, _count, _end_time, _finite,
                   _flag, _keys, _linspace, _states, _tolerance, _with_values, _known, status_message, _fixed_steps,
                   _DEFAULT_MAX_EVENTS, _EVENT_ROOM, RegularisedLawWarning,
                   _physical, MAX_ROWS, model_notes, _warn_model_steps, preset_arrays, _raise_failure,
                   _Call, _CALLS, _GRID_CACHE_ROWS, _STOP_CHECK_STEPS, _execute, _keep)
from .outputs import atomic_write
from .signal import Signal, SignalLike, as_signal
from .energy import check_result

__all__ = ["Model", "ModelWarning"]

#: The library's kinds of model element (stickslip_user_model's ELEM_*), as messages name them.
_ELEMENTS = {1: "body", 2: "spring", 3: "damper", 4: "force", 5: "contact", 6: "signal", 7: "drive"}
#: What a drive prescribes, by the library's code (stickslip_user_model's DRIVE_*).
_DRIVES = {"position": 1, "velocity": 2}
#: The laws with jumps (modes: the registry's n_modes > 0), which implicit_euler and galpha
#: solve over their modes on a model (stickslip_modal_contacts), and those methods.
_JUMP_LAWS = tuple(law for law in LAWS if REGISTRY["law"][law]["modes"] > 0)
_MODAL_METHODS = ("implicit_euler", "galpha")


class ModelWarning(UserWarning):
    """A model that runs but is probably not what was meant: a normal force that never closes
    its contact, or a tolerance coarser than a contact's velocity band."""


@dataclass
class _Body:
    mass: float
    x0: float
    v0: float
    name: str


@dataclass
class _Drive:
    body: int
    kind: str          # "position" [m] or "velocity" [m/s]
    signal: Signal


@dataclass
class _Contact:
    a: int
    b: int | None
    law: str
    normal_force: Signal
    surface_velocity: Signal | None
    params: dict[str, float] = field(default_factory=dict)
    #: the law's initial internal states (empty: all 0); set by stickslip.steady to start a run
    #: on a periodic orbit
    z0: tuple[float, ...] = ()


class Model:
    """A system of bodies, springs, dampers, forces and friction contacts (see the module).

    Elements are added with `add_body`, `add_spring`, `add_damper`, `add_force`,
    `add_contact` and `add_drive`; each is checked as it is added (a ValueError naming the
    element). Run it
    with ``stickslip.simulate(model, method=..., t_end=...)``; save and load it with
    `to_toml` and `from_toml`; a built-in scene as a model: `from_scene`.
    """

    def __init__(self) -> None:
        self.bodies: list[_Body] = []
        self.springs: list[tuple[int, int | None, float, float]] = []
        self.dampers: list[tuple[int, int | None, float]] = []
        self.forces: list[tuple[int, Signal]] = []
        self.contacts: list[_Contact] = []
        self.drives: list[_Drive] = []
        #: True: the adaptive methods' relative tolerance acts on each contact's slip (a body's
        #: velocity sized by its contacts' slips); False: on |y| component by component, as a
        #: scene's preset runs (`from_scene` sets it, so that its model runs as the scene)
        self.slip_error_size: bool = True

    # -- building ----------------------------------------------------------------------
    @property
    def n_bodies(self) -> int:
        """Number of bodies."""
        return len(self.bodies)

    def _body(self, element: str, role: str, index: Any, ground: bool = True) -> int | None:
        """A body index of the model (or None, the ground, where allowed), else ValueError."""
        if index is None and ground:
            return None
        if isinstance(index, (bool, np.bool_)) or not isinstance(index, (int, np.integer)) \
                or not 0 <= index < self.n_bodies:
            names = f"0 .. {self.n_bodies - 1}" if self.n_bodies else "none yet: add_body first"
            raise ValueError(f"{element}: {role} must be a body index ({names})"
                             f"{' or None (the ground)' if ground else ''}, got {index!r}")
        return int(index)

    def _pair(self, element: str, a: Any, b: Any, ground_a: bool = False) -> tuple[int | None, int | None]:
        ia = self._body(element, "a", a, ground=ground_a and b is not None)
        ib = self._body(element, "b", b, ground=ia is not None)
        if ia == ib:
            raise ValueError(f"{element}: a and b are the same body ({ia}); b = None is the ground")
        return ia, ib  # type: ignore[return-value]

    def label(self, index: int | None) -> str:
        """The name of body `index` ("ground" for None)."""
        return "ground" if index is None else self.bodies[index].name

    def add_body(self, mass: float, x0: float = 0.0, v0: float = 0.0, name: str | None = None) -> int:
        """Add a body of `mass` [kg] (an inertia [kg m^2] for a rotating part) at `x0` [m]
        moving at `v0` [m/s]; its index, from 0. `name` (default "body<index>") appears in
        messages and in TOML files."""
        i = self.n_bodies
        where = f"body {i}"
        mass = _finite(f"{where}: mass", mass, "> 0 [kg]")
        if not mass > 0.0:
            raise ValueError(f"{where}: mass must be > 0 [kg], got {mass!r}")
        name = f"body{i}" if name is None else name
        if not isinstance(name, str) or not name or name == "ground" or any(b.name == name for b in self.bodies):
            raise ValueError(f"{where}: name must be a new non-empty string other than 'ground', got {name!r}")
        self.bodies.append(_Body(mass, _finite(f"{where}: x0", x0, "[m]"), _finite(f"{where}: v0", v0, "[m/s]"),
                                 name))
        return i

    def add_spring(self, a: int, b: int | None, k: float, rest_length: float = 0.0) -> None:
        """Add a spring of stiffness `k` [N/m] between bodies `a` and `b` (None: the ground),
        relaxed where x_a - x_b = `rest_length` [m]."""
        where = f"spring {len(self.springs)}"
        ia, ib = self._pair(where, a, b)
        k = _finite(f"{where}: k", k, ">= 0 [N/m]")
        if k < 0.0:
            raise ValueError(f"{where}: k must be >= 0 [N/m], got {k!r}")
        self.springs.append((ia, ib, k, _finite(f"{where}: rest_length", rest_length, "[m]")))

    def add_damper(self, a: int, b: int | None, c: float) -> None:
        """Add a damper `c` [N s/m] between bodies `a` and `b` (None: the ground)."""
        where = f"damper {len(self.dampers)}"
        ia, ib = self._pair(where, a, b)
        c = _finite(f"{where}: c", c, ">= 0 [N s/m]")
        if c < 0.0:
            raise ValueError(f"{where}: c must be >= 0 [N s/m], got {c!r}")
        self.dampers.append((ia, ib, c))

    def add_force(self, body: int, force: SignalLike) -> None:
        """Add a force on `body`: a number [N] or a `stickslip.signal` of time."""
        where = f"force {len(self.forces)}"
        self.forces.append((self._body(where, "body", body, ground=False), as_signal(force, f"{where}: force")))

    def add_contact(self, a: int, b: int | None, law: str, normal_force: SignalLike,
                    surface_velocity: SignalLike = 0.0, **law_params: float) -> None:
        """Add a friction contact between bodies `a` and `b` (None: the ground).

        Parameters
        ----------
        a, b : int or None
            The bodies; the friction force on `a` opposes the slip
            s = v_a - v_b - surface_velocity and `b` gets the opposite force. One of them may
            be the ground (None): with ``a=None`` the law sees the ground's slip under body
            `b`, s = -v_b - surface_velocity (the scenes' belt, `from_scene`).
        law : str
            The contact's friction law, one of `stickslip.LAWS`.
        normal_force : float or Signal
            The normal force [N]; where it is zero or negative the contact is open (no
            friction), as a disengaged clutch.
        surface_velocity : float or Signal, optional
            The velocity [m/s] of a surface driven under `a` (a belt); 0 by default.
        **law_params : float
            The law's parameters (names: ``stickslip.REGISTRY["law"][law]["params"]``;
            defaults as for the scenes), range-checked when the model runs.
        """
        n = len(self.contacts)
        ia, ib = self._pair(f"contact {n}", a, b, ground_a=True)
        where = f"contact {n} ({self.label(ia)}-{self.label(ib)})"
        _choice("law", law, LAWS)
        allowed = REGISTRY["law"][law]["params"]
        unknown = set(law_params) - set(allowed)
        if unknown:
            raise ValueError(f"{where}: law {law!r} has no parameter(s) {', '.join(sorted(unknown))} "
                             f"(its parameters: {', '.join(allowed)})")
        params = {k: _finite(f"{where}: {k}", v, "see REGISTRY") for k, v in law_params.items()}
        surface = None if (not isinstance(surface_velocity, Signal) and surface_velocity == 0.0) \
            else as_signal(surface_velocity, f"{where}: surface_velocity")
        normal = as_signal(normal_force, f"{where}: normal_force")
        low, high = normal.bounds()
        if high < 0.0:
            given = f"{low!r} N" if normal.kind == "constant" else f"{normal!r}, at most {high:.6g} N at every time"
            warnings.warn(f"{where}: normal_force is negative ({given}): the contact stays open, with no friction, "
                          "for the whole run; give the normal force's magnitude (>= 0) if it is meant to press",
                          ModelWarning, stacklevel=2)
        self.contacts.append(_Contact(ia, ib, law, normal, surface, params))

    def add_drive(self, body: int, position: SignalLike | None = None,
                  velocity: SignalLike | None = None) -> None:
        """Prescribe the motion of `body`: its `position` [m] or its `velocity` [m/s] (give
        exactly one) follows the signal exactly under every method (a kinematic constraint).

        The body leaves the state: each element joined to it acts on the other body as an
        element on the ground plus a signal (a spring k: the force k (x_d(t) + rest_length); a
        damper c: c v_d(t); a contact: a surface moving at v_d(t)). Its position and velocity
        are in the result's `x` and `v` rows as for any body, and the force the drive applies
        to it, m a_d minus the other forces on it, in ``result.drive_force[:, i]`` (drive i, in
        the order added).

        Parameters
        ----------
        body : int
            The driven body; its mass counts in the drive's force only. With `position` its x0
            and v0 are not read; with `velocity` its position is x0 plus the integral of the
            signal from t = 0.
        position : float or Signal, optional
            The position [m]: a signal without steps (a jump in position has no velocity).
        velocity : float or Signal, optional
            The velocity [m/s]: sums, differences and multiples (a number times a signal) of
            constants, steps, ramps, sines and tables (their integrals are exact).
        """
        where = f"drive {len(self.drives)}"
        i = self._body(where, "body", body, ground=False)
        if (position is None) == (velocity is None):
            raise ValueError(f"{where}: give exactly one of position= and velocity=, got "
                             f"{'both' if position is not None else 'neither'}")
        where = f"{where} ({self.label(i)})"
        if any(d.body == i for d in self.drives):
            raise ValueError(f"{where}: body {self.label(i)!r} already has a drive")
        kind = "position" if position is not None else "velocity"
        sig = as_signal(position if position is not None else velocity, f"{where}: {kind}")
        bad = _drive_problem(sig, kind)
        if bad:
            raise ValueError(f"{where}: {kind} {bad}")
        self.drives.append(_Drive(i, kind, sig))

    def driven(self, index: int | None) -> bool:
        """True when body `index` has a drive (the ground: False)."""
        return index is not None and any(d.body == index for d in self.drives)

    def element_label(self, kind: str, i: int) -> str:
        """'kind i (A-B)' with the bodies' names as the user gave them, as messages name
        element `i` of `kind` (body, spring, damper, force, contact, drive, signal)."""
        name = self.label
        if kind == "contact":
            return self.contact_label(i)
        if kind in ("spring", "damper") and i < len(getattr(self, kind + "s")):
            a, b = getattr(self, kind + "s")[i][:2]
            return f"{kind} {i} ({name(a)}-{name(b)})"
        if kind == "force" and i < len(self.forces):
            return f"force {i} ({name(self.forces[i][0])})"
        if kind == "drive" and i < len(self.drives):
            return f"drive {i} ({name(self.drives[i].body)})"
        if kind == "body" and i < self.n_bodies:
            return f"body {i} ({name(i)})"
        return f"{kind} {i}"

    def contact_label(self, i: int) -> str:
        """'contact i (A-B)' with the bodies' names, as messages name contact `i`."""
        c = self.contacts[i]
        return f"contact {i} ({self.label(c.a)}-{self.label(c.b)})"

    # -- what the library reads -----------------------------------------------------------
    def n_states(self) -> int:
        """Size of the state: positions, velocities, then every contact's law states."""
        return 2 * self.n_bodies + sum(self._law_states(i)[0] for i in range(len(self.contacts)))

    def _law_states(self, i: int) -> tuple[int, tuple[str, ...]]:
        c = self.contacts[i]
        try:
            return _states(c.law, tuple(sorted(c.params.items())))
        except ValueError as err:
            raise ValueError(f"{self.contact_label(i)}: {err}") from None

    def state_labels(self) -> tuple[str, ...]:
        """Name and unit of each law state, 'contact i: z [m]', in the order of the state."""
        return tuple(f"contact {i}: {lab}" for i in range(len(self.contacts)) for lab in self._law_states(i)[1])

    def arrays(self) -> dict[str, Any]:
        """The model as the library's arrays (body indices from 1, 0 the ground)."""
        if not self.bodies:
            raise ValueError("model: has no bodies (add_body first)")
        if self.drives and all(self.driven(i) for i in range(self.n_bodies)):
            raise ValueError(f"model: every body has a drive ({', '.join(b.name for b in self.bodies)}): "
                             "leave at least one body free")
        for i, c in enumerate(self.contacts):
            if all(body is None or self.driven(body) for body in (c.a, c.b)):
                raise ValueError(f"{self.contact_label(i)}: each side is driven or the ground, so its friction "
                                 "moves no free body; remove the contact or a drive")
        one = lambda i: 0 if i is None else i + 1  # noqa: E731
        signals: list[Signal] = []

        def sig(s: Signal | None) -> int:
            if s is None:
                return 0
            signals.append(s)
            return len(signals)
        keys: list[str] = []
        vals: list[float] = []
        ptr = [1]
        for c in self.contacts:
            keys.extend(c.params)
            vals.extend(c.params.values())
            ptr.append(len(keys) + 1)
        con_n = [sig(c.normal_force) for c in self.contacts]
        con_w = [sig(c.surface_velocity) for c in self.contacts]
        frc_sig = [sig(s) for _, s in self.forces]
        drv_sig = [sig(d.signal) for d in self.drives]
        tables: list[float] = []
        tvalues: list[float] = []
        ops: list[tuple[int, tuple[float, ...]]] = []
        start = [1]
        for s in signals:
            ops.extend(s.program(tables, tvalues))
            start.append(len(ops) + 1)
        def rows(items: list[tuple[float, ...]], width: int) -> np.ndarray:
            return np.asfortranarray(np.asarray(items, dtype=np.float64).reshape(-1, width).T)
        return dict(
            bodies=rows([(b.mass, b.x0, b.v0) for b in self.bodies], 3),
            springs=rows([(one(a), one(b), k, l0) for a, b, k, l0 in self.springs], 4),
            dampers=rows([(one(a), one(b), c) for a, b, c in self.dampers], 3),
            forces=rows([(a + 1, s) for (a, _), s in zip(self.forces, frc_sig)], 2),
            contacts=rows([(one(c.a), one(c.b), LAWS.index(c.law) + 1, n, w)
                           for c, n, w in zip(self.contacts, con_n, con_w)], 5),
            con_ptr=np.asarray(ptr, dtype=np.int32), pkeys=" ".join(keys), pvals=np.asarray(vals, dtype=np.float64),
            signals=rows([(o, *a) for o, a in ops], 5), sig_start=np.asarray(start, dtype=np.int32),
            tables=rows(list(zip(tables, tvalues)), 2),
            drives=rows([(d.body + 1, _DRIVES[d.kind], s) for d, s in zip(self.drives, drv_sig)], 3))

    # -- files ------------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The model as plain data: the content of its TOML file (bodies by name)."""
        name = self.label
        out: dict[str, Any] = {"body": [{"name": b.name, "mass": b.mass, "x0": b.x0, "v0": b.v0} for b in self.bodies]}
        if self.springs:
            out["spring"] = [{"a": name(a), "b": name(b), "k": k, "rest_length": l0} for a, b, k, l0 in self.springs]
        if self.dampers:
            out["damper"] = [{"a": name(a), "b": name(b), "c": c} for a, b, c in self.dampers]
        if self.forces:
            out["force"] = [{"body": name(a), "force": s.to_dict()} for a, s in self.forces]
        if self.contacts:
            out["contact"] = []
            for c in self.contacts:
                row: dict[str, Any] = {"a": name(c.a), "b": name(c.b), "law": c.law,
                                       "normal_force": c.normal_force.to_dict()}
                if c.surface_velocity is not None:
                    row["surface_velocity"] = c.surface_velocity.to_dict()
                if c.params:
                    row["params"] = dict(c.params)
                out["contact"].append(row)
        if self.drives:
            out["drive"] = [{"body": name(d.body), d.kind: d.signal.to_dict()} for d in self.drives]
        if not self.slip_error_size:
            out["settings"] = [{"slip_error_size": False}]
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "Model":
        """The inverse of `to_dict`; ValueError naming the bad entry."""
        unknown = set(data) - {"body", "spring", "damper", "force", "contact", "drive", "settings"}
        if unknown:
            raise ValueError(f"model file: unknown section(s) {', '.join(sorted(unknown))} "
                             "(accepted: body, spring, damper, force, contact, drive, settings)")
        if not data.get("body"):
            raise ValueError("model file: no [[body]] table: a model needs at least one body "
                             "([[body]] with mass = ..., and optionally name, x0, v0)")
        for section, rows in data.items():
            if not isinstance(rows, list):
                raise ValueError(f"model file: {section} must be an array of tables, [[{section}]], "
                                 f"got {section} = {rows!r}")
        m = cls()
        for i, b in enumerate(data.get("body", [])):
            _fields(f"body {i}", b, {"mass"}, {"name", "x0", "v0"})
            m.add_body(b["mass"], b.get("x0", 0.0), b.get("v0", 0.0), b.get("name"))
        index = {b.name: i for i, b in enumerate(m.bodies)}

        def body(where: str, value: Any, ground: bool = True) -> int | None:
            if value == "ground" and ground:
                return None
            if value not in index:
                raise ValueError(f"{where}: unknown body {value!r} (bodies: {', '.join(index)}"
                                 f"{', ground' if ground else ''})")
            return index[value]
        for i, s in enumerate(data.get("spring", [])):
            _fields(f"spring {i}", s, {"a", "b", "k"}, {"rest_length"})
            m.add_spring(body(f"spring {i}", s["a"]), body(f"spring {i}", s["b"]), s["k"], s.get("rest_length", 0.0))
        for i, d in enumerate(data.get("damper", [])):
            _fields(f"damper {i}", d, {"a", "b", "c"}, set())
            m.add_damper(body(f"damper {i}", d["a"]), body(f"damper {i}", d["b"]), d["c"])
        for i, f in enumerate(data.get("force", [])):
            _fields(f"force {i}", f, {"body", "force"}, set())
            m.add_force(body(f"force {i}", f["body"], False), Signal.from_dict(f["force"], f"force {i}"))
        for i, c in enumerate(data.get("contact", [])):
            where = f"contact {i}"
            _fields(where, c, {"a", "b", "law", "normal_force"}, {"surface_velocity", "params"})
            surface = Signal.from_dict(c["surface_velocity"], where) if "surface_velocity" in c else 0.0
            m.add_contact(body(where, c["a"]), body(where, c["b"]), c["law"],
                          Signal.from_dict(c["normal_force"], where), surface, **c.get("params", {}))
        for i, d in enumerate(data.get("drive", [])):
            where = f"drive {i}"
            _fields(where, d, {"body"}, {"position", "velocity"})
            given = {k: Signal.from_dict(d[k], f"{where}: {k}") for k in ("position", "velocity") if k in d}
            if len(given) != 1:
                raise ValueError(f"{where}: give exactly one of position and velocity, got "
                                 f"{', '.join(given) if given else 'neither'}")
            m.add_drive(body(where, d["body"], False), **given)
        settings = data.get("settings", [])
        if len(settings) > 1:
            raise ValueError(f"model file: at most one [[settings]] table, got {len(settings)}")
        for row in settings:
            _fields("settings", row, set(), {"slip_error_size"})
            value = row.get("slip_error_size", True)
            if not isinstance(value, bool):
                raise ValueError(f"settings: slip_error_size must be true or false, got {value!r}")
            m.slip_error_size = value
        return m

    def to_toml(self, path: str | os.PathLike) -> None:
        """Write the model to a TOML file, whole or not at all (a temporary file renamed).
        The schema: docs/guide/models.md."""
        write_whole(path, _toml(self.to_dict()))

    @classmethod
    def from_toml(cls, path: str | os.PathLike) -> "Model":
        """Read a model from a TOML file written by `to_toml` or by hand (docs/guide/models.md)."""
        try:
            with open(path, "rb") as fh:
                data = tomllib.load(fh)
        except tomllib.TOMLDecodeError as err:
            raise ValueError(f"{os.fspath(path)}: not a valid TOML file ({err})") from None
        try:
            return cls.from_dict(data)
        except ValueError as err:
            raise ValueError(f"{os.fspath(path)}: {err}") from None

    # -- the built-in scenes ----------------------------------------------------------------
    @classmethod
    def from_scene(cls, scene: str, law: str, x0: Any = 0.0, v0: Any = None, *, per_unit_mass: bool = False,
                   **params: float) -> "Model":
        """A built-in scene as a model: the model its preset builds in the library
        (``stickslip_presets``, read through the wrapper: one definition), which ``simulate``
        runs with the same kernel as the scene, to the last bit.

        Every preset is per unit mass, as the scene's equations: "slope": one body of mass 1
        pulled down the slope by g sin(theta) on a contact with the ground, normal force
        g cos(theta); "belt": a body of mass 1 on a spring k/m to the ground, on a belt
        moving at v_b (the contact's side a is the ground, its surface velocity -v_b: the law
        sees the belt's slip v_b - v under the body, as in the scene), normal force g;
        "chain": n_blocks such bodies, springs (k + k_p)/m to the ground for block 0, k_p/m
        for the others, k_c/m between neighbours, normal forces g (1 + perturbation r_i).

        The model returned has the scene's physical masses (per_unit_mass=False, the default):
        on the belt and the chain each body of mass m, and every spring, damper, force and normal
        force of the preset times m, so that an element you add (a damper c [N s/m], a second
        body) means what it says and the contact forces are in newtons; it gives the scene's
        motion to rounding. per_unit_mass=True returns the preset itself, which ``simulate``
        runs with the same kernel as the scene, to the last bit. The model's `slip_error_size`
        is False, as the scenes' (the adaptive methods' tolerance on |y|). `x0`, `v0` as for
        `simulate` (v0 on the chain defaults to v_b, on the others to 0); other keywords are
        the scene's and the law's parameters.
        """
        _choice("scene", scene, tuple(REGISTRY["scene"]))
        _choice("law", law, LAWS)
        given = _physical(params)
        scene_params = set(REGISTRY["scene"][scene]["params"])
        law_names = set(REGISTRY["law"][law]["params"])
        unknown = set(given) - scene_params - law_names
        if unknown:
            raise ValueError(f"{', '.join(sorted(unknown))}: not a parameter of scene {scene!r} or law {law!r}")
        mass, springs, dampers, forces, contacts = preset_arrays(scene, law, given)
        if not isinstance(per_unit_mass, bool):
            raise ValueError(f"per_unit_mass: must be True or False, got {per_unit_mass!r}")
        # the scene's mass (the slope's cancels: its preset's body is the slope's unit mass)
        scale = 1.0 if per_unit_mass or "m" not in scene_params else float(_known(given)["m"])
        nb = mass.size
        if scene == "chain" and v0 is None:
            v0 = _known(given)["v_b"]          # every block stuck on the belt, as simulate's chain
        xs = np.broadcast_to(np.asarray(_finite("x0", x0, "[m]") if nb == 1 else x0, dtype=np.float64), (nb,))
        vs = np.broadcast_to(np.asarray(_finite("v0", 0.0 if v0 is None else v0, "[m/s]") if nb == 1 else v0,
                                        dtype=np.float64), (nb,))
        body = lambda j: None if j == 0 else int(j) - 1  # noqa: E731  (the library's index: 0 the ground)
        m = cls()
        m.slip_error_size = False
        for i in range(nb):
            m.add_body(scale * float(mass[i]), float(xs[i]), float(vs[i]))
        for a, b, k, rest in springs.T:
            m.add_spring(body(a), body(b), scale * float(k), float(rest))
        for a, b, c in dampers.T:
            m.add_damper(body(a), body(b), scale * float(c))
        for j, f in forces.T:
            m.add_force(body(j), scale * float(f))
        lp = {k: v for k, v in given.items() if k in law_names}
        for a, b, normal, surface in contacts.T:
            m.add_contact(body(a), body(b), law, scale * float(normal), float(surface), **lp)
        return m

    def run_model(self, **kwargs: Any) -> Result:
        """Run the model: what ``stickslip.simulate(model, method=..., t_end=..., ...)`` calls
        (keywords as there)."""
        return simulate_model(self, **kwargs)

    def __repr__(self) -> str:
        drives = f", {len(self.drives)} drives" if self.drives else ""
        return (f"Model({self.n_bodies} bodies, {len(self.springs)} springs, {len(self.dampers)} dampers, "
                f"{len(self.forces)} forces, {len(self.contacts)} contacts{drives})")


def write_whole(path: str | os.PathLike, data: str | bytes) -> None:
    """Write `data` to `path` whole or not at all (stickslip.outputs.atomic_write)."""
    atomic_write(path, lambda fh: fh.write(data), binary=isinstance(data, bytes))


def _drive_problem(sig: Signal, kind: str) -> str:
    """Why `sig` cannot drive a body's `kind` ("position" or "velocity"), or "" when it can:
    a position has no steps (their derivative is not a function); a velocity's integral is
    exact for sums and differences of primitives and multiples of signals by numbers only."""
    if kind == "position":
        return ("has a step, whose derivative is not a function (a position cannot jump); use a "
                "ramp, or drive the velocity") if _has(sig, "step") else ""
    def integrable(s: Signal) -> bool:
        if s.kind in ("add", "sub"):
            return all(integrable(c) for c in s.children)
        if s.kind == "mul":
            a, b = s.children
            return (a.kind == "constant" and integrable(b)) or (b.kind == "constant" and integrable(a))
        return True
    return "" if integrable(sig) else ("multiplies two signals that are not numbers, whose integral has no "
                                       "closed form here; give the position instead")


def _has(sig: Signal, kind: str) -> bool:
    """True when `sig` has a primitive of `kind`."""
    return sig.kind == kind or any(_has(c, kind) for c in sig.children)


def _fields(where: str, row: Any, required: set[str], optional: set[str]) -> None:
    """A TOML entry has its required fields and no others, else ValueError naming it."""
    if not isinstance(row, dict):
        raise ValueError(f"{where}: must be a table, got {row!r}")
    missing = required - set(row)
    extra = set(row) - required - optional
    if missing:
        raise ValueError(f"{where}: missing {', '.join(sorted(missing))}")
    if extra:
        raise ValueError(f"{where}: unknown field(s) {', '.join(sorted(extra))} "
                         f"(accepted: {', '.join(sorted(required | optional))})")


def _toml_value(v: Any) -> str:
    """A value in TOML's inline syntax (numbers exactly: repr round-trips a float)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"model file: {v!r} has no TOML form")
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise ValueError(f"model file: cannot write {v!r}")


def _toml(data: Mapping[str, Any]) -> str:
    """A model's data as TOML: one array of tables per kind of element."""
    lines = ["# A stickslip model (stickslip.Model.to_toml; schema: docs/guide/models.md)", ""]
    for section, rows in data.items():
        for row in rows:
            lines.append(f"[[{section}]]")
            lines.extend(f"{k} = {_toml_value(v)}" for k, v in row.items())
            lines.append("")
    return "\n".join(lines)


def check_method(model: Model, method: str) -> None:
    """ValueError, naming the contact, when `method` cannot take the laws of `model`'s
    contacts (set-valued methods take coulomb and stribeck only; implicit_euler and galpha
    take laws that jump only when every contact's law jumps)."""
    _choice("method", method, METHODS)
    info = REGISTRY["method"][method]
    laws = [c.law for c in model.contacts]
    if info["laws"]:
        bad = [i for i, law in enumerate(laws) if law not in info["laws"]]
        if bad:
            raise ValueError(f"{model.contact_label(bad[0])}: method {method!r} takes the laws "
                             f"{', '.join(info['laws'])} only, got {laws[bad[0]]!r} (give every contact a "
                             "set-valued law, or use an event-free method)")
    if method in _MODAL_METHODS:
        jumps = [law in _JUMP_LAWS for law in laws]
        if any(jumps) and not all(jumps):
            smooth = jumps.index(False)
            raise ValueError(f"{model.contact_label(smooth)}: {method} solves a model with laws that jump "
                             f"({', '.join(_JUMP_LAWS)}) over their modes, every contact's law then jumping; "
                             f"this contact's law is {laws[smooth]!r} (give every contact a law that jumps, "
                             "or none)")


def _input_error(model: Model, status: int, elem_kind: int, elem_index: int) -> ValueError:
    """The ValueError of a bad-input status of a model's call, naming the element it names."""
    message = status_message(status)
    if elem_kind == 5:
        c = model.contacts[elem_index - 1]
        message = f"{model.contact_label(elem_index - 1)}: " + _with_values(message, _known(c.params))
    elif elem_kind:
        message = f"{model.element_label(_ELEMENTS[elem_kind], elem_index - 1)}: {message}"
    return ValueError(message)


def run_controls(model: Model, method: str, controls: Mapping[str, Any], max_steps: int | None = None,
                 every_step: bool = False, said: list[tuple[str, type[Warning]]] | None = None
                 ) -> tuple[dict[str, float], np.ndarray, np.ndarray]:
    """The controls of a run of `model` by `method` (the method's defaults, then the given
    ones, each checked), and the tolerances rtol, atol as arrays: what `simulate_model`
    passes to the wrapper (and `stickslip.steady` to the orbit solver). ValueError naming a
    control that is not the method's, a value that is not finite, or h missing. `said`: a
    list that receives the warnings issued (`_check_band`'s), (message, category) in order."""
    info = REGISTRY["method"][method]
    n = model.n_states()
    ctl = {k: _flag(v) for k, v in CONTROL_DEFAULTS.items() if k in info["controls"]}
    for name, value in controls.items():
        if name not in info["controls"]:
            raise ValueError(f"{name}: not a control of method {method!r} "
                             f"(its controls: {', '.join(info['controls'])})")
        ctl[name] = _flag(value)
    rtol = _tolerance("rtol", ctl.pop("rtol", 1.0), n)
    atol = _tolerance("atol", ctl.pop("atol", 1.0), n)
    if info["adaptive"] and not info["laws"]:        # dopri5, dop853, radau5: the laws' bands
        _check_band(model, method, float(np.max(rtol)), said)
    for name, value in ctl.items():
        ctl[name] = _finite(name, value, "see simulate()")
    if "h" in info["controls"] and "h" not in ctl:
        raise ValueError(f"h: required for method {method!r} (finite, > 0 [s])")
    if max_steps is None:
        max_steps = 10**6 if (every_step and info["adaptive"]) else 10**8
    ctl["max_steps"] = float(_count("max_steps", max_steps))
    return ctl, rtol, atol


def orbit_model(model: Model, method: str, y0: np.ndarray, period: float, autonomous: bool,
                controls: Mapping[str, Any], *, tol: float, max_iter: int, fd_newton: float,
                fd_monodromy: float) -> dict[str, Any]:
    """One call of the Fortran orbit solver (stickslip_orbit) on `model`: single shooting by
    `method` from the guess (y0, period), forced or autonomous, and the monodromy by central
    differences with its eigenvalues; max_iter = 0: the monodromy at the guess only. Returns
    y0, period, monodromy, multipliers (largest modulus first), residual, iterations, runs,
    trivial (index or None), stable and status (STATUS_OK, the solver's SS_ORBIT_* or a run's
    outcome); ValueError for bad input, naming the element as `simulate` does."""
    ctl, rtol, atol = run_controls(model, method, controls)
    arrays = model.arrays()
    ckeys, cvals = _keys(ctl)
    y, period_out, mono, mre, mim, info, status, elem_kind, elem_index = _ext.orbit_model(
        *(arrays[k] for k in ("bodies", "springs", "dampers", "forces", "contacts", "con_ptr", "pkeys", "pvals",
                              "signals", "sig_start", "tables", "drives")),
        method, np.asarray(y0, dtype=np.float64), float(period), int(autonomous), rtol, atol, ckeys, cvals,
        float(tol), int(max_iter), float(fd_newton), float(fd_monodromy), 1, int(model.slip_error_size))
    status = int(status)
    if status <= _FIRST_INPUT_CODE:
        raise _input_error(model, status, int(elem_kind), int(elem_index))
    mult = mre + 1j * mim
    if np.all(mim == 0.0):
        mult = mre.copy()
    return {"y0": y, "period": float(period_out), "monodromy": mono, "multipliers": mult, "residual": float(info[0]),
            "iterations": int(info[1]), "runs": int(info[2]), "trivial": int(info[3]) - 1 if info[3] else None,
            "stable": bool(info[4]), "status": status}


def event_room(method: str, ctl: Mapping[str, Any]) -> int:
    """Rows kept for a run's stick/slip events: its max_events (default, capped) where the
    method reads that control, none otherwise."""
    if "max_events" not in REGISTRY["method"][method]["controls"]:
        return 0
    return int(min(max(ctl.get("max_events", _DEFAULT_MAX_EVENTS), 0), _EVENT_ROOM))


def initial_state(model: "Model", arrays: Mapping[str, Any]) -> np.ndarray:
    """The state a model's run starts from: every body's x0, then v0, then each contact's law
    states z0 (0 where not given); `arrays` is `model.arrays()`."""
    y0 = np.zeros(model.n_states())
    y0[:model.n_bodies] = arrays["bodies"][1]
    y0[model.n_bodies:2 * model.n_bodies] = arrays["bodies"][2]
    first = 2 * model.n_bodies
    for i, c in enumerate(model.contacts):
        nz = model._law_states(i)[0]
        if c.z0:
            y0[first:first + nz] = c.z0
        first += nz
    return y0


def simulate_model(model: Model, *, method: str, t_end: float, n_out: int | None = None,
                   every_step: bool = False, max_steps: int | None = None, **controls: Any) -> Result:
    """Run `model` (what ``stickslip.simulate(model, method=..., ...)`` does; see there). A run
    of equal arguments on a model of equal content (`_run_key`) is not validated again: the
    warnings its validation issued are issued again, as they were, and its setting is run."""
    if not isinstance(model, Model):
        raise ValueError(f"model: must be a stickslip.Model, got {type(model).__name__}")
    key, signals = _run_key(model, method, t_end, n_out, every_step, max_steps, controls)
    run = _CALLS.get(key) if key is not None else None
    if run is not None:
        for message, category, level in run.warnings:
            warnings.warn(message, category, stacklevel=level)
    else:
        check_method(model, method)
        notes = model_notes(model, method, stacklevel=4)
        steps = _warn_model_steps(model, method, t_end, controls, stacklevel=5)    # the caller of simulate
        info = REGISTRY["method"][method]
        arrays = model.arrays()
        t_end = _end_time(t_end)
        band: list[tuple[str, type[Warning]]] = []
        ctl, rtol, atol = run_controls(model, method, controls, max_steps, every_step, band)
        if every_step:
            if n_out is not None:
                raise ValueError("n_out: give either n_out or every_step, not both")
            rows = int(min(ctl["max_steps"], MAX_ROWS - 1)) + 1
            if not info["adaptive"] and ctl.get("h", 0.0) > 0.0:
                rows = min(rows, int(math.ceil(t_end / ctl["h"])) + 2)
            ctl["every_step"] = 1.0
        else:
            n_out = _count("n_out", 1001 if n_out is None else n_out, 1, MAX_ROWS)
            rows = 0
        ckeys, cvals = _keys(ctl)
        # the model's setting built once (kept in simulate's cache, keyed on its arrays) and run
        # as a scene's is: run_prepared through _runner, which builds the Result (with its
        # drives' forces)
        call = _model_call(model, arrays, method, t_end, initial_state(model, arrays), rtol, atol, ckeys, cvals,
                           rows, n_out, event_room(method, ctl),
                           info["adaptive"] or _fixed_steps(t_end, ctl.get("h", 0.0)) >= _STOP_CHECK_STEPS // 2)
        # the warnings again with their stacklevels counted from here: the notes' and the
        # steps' at simulate's caller, _check_band's at Model.run_model
        said = ([(m, RegularisedLawWarning, 4) for m in notes] + [(m, c, 4) for m, c in steps]
                + [(m, c, 2) for m, c in band])
        run = _ModelRun(call, tuple(said), tuple(notes), {**ctl, "rtol": rtol, "atol": atol}, arrays, signals,
                        [] if key is not None else None)
        if key is not None:
            _keep(key, run)
    call = run.call
    result = _execute(call, None if call.grid is not None or call.rows else _linspace(call.t_end, call.n_out))
    return _checked_run(model, method, result, run.notes, run.controls, run.arrays, run.memo)


class _ModelRun:
    """A run of a Model as simulate was called (`_run_key`), validated once and kept in
    simulate's cache: the _Call of its setting (shared by the runs of models of equal arrays,
    `_model_call`), the warnings its validation issued (message, category, stacklevel counted
    from simulate_model), the notes among them, the controls its consistency check reads, the
    model's arrays, the model's signals, whose ids its key holds (kept here, so that no
    other signal takes one of those ids while the key is kept), and the memo of its
    consistency check (`check_result`: what it reads of the model and the output grid; None
    for a run not kept, whose check finds those by the model's arrays)."""

    __slots__ = ("call", "warnings", "notes", "controls", "arrays", "signals", "memo")

    def __init__(self, call: _Call, said: tuple[tuple[str, type[Warning], int], ...], notes: tuple[str, ...],
                 controls: Mapping[str, Any], arrays: Mapping[str, Any], signals: tuple[Any, ...] | None,
                 memo: list[Any] | None) -> None:
        self.call, self.warnings, self.notes = call, said, notes
        self.controls, self.arrays, self.signals, self.memo = controls, arrays, signals, memo


#: The first item of the key of a Model's run in simulate's cache: no key of a scene's run
#: (simulate's arguments, the scene's name first) equals one of these.
_RUN_KEY = object()
#: The types of simulate's arguments a run's key takes (others: validated each time).
_KEY_TYPES = (int, float, bool, str, type(None))


def _run_key(model: Model, method: Any, t_end: Any, n_out: Any, every_step: Any, max_steps: Any,
             controls: Mapping[str, Any]) -> tuple[tuple | None, tuple[Any, ...] | None]:
    """The key of a run of `model` in simulate's cache, made without the model's arrays, and
    the model's signals: the counts of each kind of element, the body indices, the names of the
    bodies, laws and law parameters, the signals by id (a Signal is immutable; the kept run
    holds them), every number of the model by its bits (packed as doubles: -0.0 is not 0.0),
    and the arguments with their types (floats by repr, exact). (None, None) for an element
    or argument of another kind (a tolerance per component): such a run is validated each
    time."""
    args = (method, t_end, n_out, every_step, max_steps, *controls.values())
    if any(type(a) not in _KEY_TYPES for a in args):
        return None, None
    try:
        nums: list[float] = []
        shape: list[Any] = [model.slip_error_size, len(model.bodies), len(model.springs), len(model.dampers),
                            len(model.forces), len(model.contacts), len(model.drives)]
        signals: list[Any] = []
        for body in model.bodies:
            nums += (body.mass, body.x0, body.v0)
            shape.append(body.name)
        for a, b, k, rest in model.springs:
            nums += (k, rest)
            shape += (a, b)
        for a, b, c in model.dampers:
            nums.append(c)
            shape += (a, b)
        for a, sig in model.forces:
            shape += (a, id(sig))
            signals.append(sig)
        for con in model.contacts:
            nums += con.params.values()
            nums += con.z0
            shape += (con.a, con.b, con.law, id(con.normal_force), id(con.surface_velocity), len(con.params),
                      *con.params, len(con.z0))
            signals += (con.normal_force, con.surface_velocity)
        for drive in model.drives:
            shape += (drive.body, drive.kind, id(drive.signal))
            signals.append(drive.signal)
        packed = struct.pack(f"{len(nums)}d", *nums)
    except (TypeError, ValueError, struct.error):
        return None, None
    given = tuple((k, type(v), repr(v)) for k, v in controls.items())
    return ((_RUN_KEY, tuple(shape), packed, *((type(a), repr(a)) for a in args[:5]), given), tuple(signals))


def _checked_run(model: Model, method: str, result: Result, notes: tuple[str, ...], controls: Mapping[str, Any],
                 arrays: Mapping[str, Any], memo: list[Any] | None) -> Result:
    """`result` of a run of `model`, raised for an early end (`_raise_failure`), else with the
    notes of its warnings and its consistency check (`check_result`, warned from simulate's
    caller)."""
    if result._raw[2] != STATUS_OK:
        _raise_failure(result, {})
    result.stats["notes"].extend(notes)
    check_result(result, method, controls, model, arrays, stacklevel=5, memo=memo)
    return result


#: The arrays of `Model.arrays` that make a model's setting, in prepare_model_run's order.
_ARRAY_KEYS = ("bodies", "springs", "dampers", "forces", "contacts", "con_ptr", "pkeys", "pvals", "signals",
               "sig_start", "tables", "drives")


def _model_call(model: Model, arrays: Mapping[str, Any], method: str, t_end: float, y0: np.ndarray,
                rtol: np.ndarray, atol: np.ndarray, ckeys: str, cvals: np.ndarray, rows: int,
                n_out: int | None, room: int, arm: bool) -> _Call:
    """The _Call of a run of `model` (prepare_model_run: the model built, specialised, with
    the method's options and its drives, once), from simulate's cache when a model of equal
    arrays ran so before (the cache is keyed on the model's content, not on the object: a
    Model is mutable); ValueError naming a bad element."""
    key = ("model", method, t_end, rows, n_out, room, bool(model.slip_error_size), ckeys, cvals.tobytes(),
           rtol.tobytes(), atol.tobytes(), y0.tobytes(),
           *((a if isinstance(a, str) else (a.shape, a.tobytes())) for a in (arrays[k] for k in _ARRAY_KEYS)))
    call = _CALLS.get(key)
    if call is not None:
        return call
    handle, status, elem_kind, elem_index = _ext.prepare_model_run(
        *(arrays[k] for k in _ARRAY_KEYS), method, y0, t_end, rtol, atol, ckeys, cvals,
        int(model.slip_error_size))
    status = int(status)
    if status != STATUS_OK:
        raise _input_error(model, status, int(elem_kind), int(elem_index))
    grid = None
    if not rows and n_out <= _GRID_CACHE_ROWS:
        grid = _linspace(t_end, n_out)
        grid.setflags(write=False)           # copied for each call (_runner)
    nb = model.n_bodies
    call = _Call(scene="model", law="+".join(dict.fromkeys(c.law for c in model.contacts)), method=method,
                 t_end=t_end, handle=int(handle), n=y0.size, resolved=None, grid=grid, n_out=n_out, rows=rows,
                 warnings=(), n_states=y0.size - 2 * nb, state_labels=model.state_labels(), used=(), known={},
                 events_room=room, n_blocks=nb, arm=arm, model=True, n_drives=len(model.drives), fast=False)
    _keep(key, call)
    return call


def slip_scale(model: Model, i: int) -> float:
    """A scale of contact `i`'s slip [m/s]: the largest speed of its surface plus its bodies'
    initial speeds (a driven body's: the largest of its velocity signal, or of its position
    signal's rate where that is known only by running it: the initial speed then)."""
    c = model.contacts[i]
    scale = max(map(abs, c.surface_velocity.bounds())) if c.surface_velocity is not None else 0.0
    for body in (c.a, c.b):
        if body is None:
            continue
        drive = next((d for d in model.drives if d.body == body), None)
        if drive is not None and drive.kind == "velocity":
            scale += max(map(abs, drive.signal.bounds()))
        else:
            scale += abs(model.bodies[body].v0)
    return scale


def _check_band(model: Model, method: str, rtol: float,
                said: list[tuple[str, type[Warning]]] | None = None) -> None:
    """A ModelWarning for each contact whose law has a velocity band (v_eps, v_s) narrower than
    rtol times the contact's slip scale (`slip_scale`): an error of rtol times the slip may
    then cross the band the law turns in. Each is also appended to `said` (when given) as
    (message, category)."""
    for i, c in enumerate(model.contacts):
        names = [k for k in ("v_eps", "v_s") if k in REGISTRY["law"][c.law]["params"]]
        if not names:
            continue
        known = _known(c.params)
        band_name = min(names, key=lambda k: known[k])
        band, scale = known[band_name], slip_scale(model, i)
        if rtol * scale > band:
            message = (f"{model.contact_label(i)}: rtol = {rtol:.3g} times the slip scale {scale:.6g} m/s "
                       f"(its surface's and bodies' speeds) is {rtol * scale:.3g} m/s, more than its law's "
                       f"{band_name} = {band:.3g} m/s: {method}'s error test may not resolve the law's band; "
                       f"take rtol <= {band / scale:.3g}")
            warnings.warn(message, ModelWarning, stacklevel=4)
            if said is not None:
                said.append((message, ModelWarning))
