"""Time signals for a `Model`: forces, normal forces and surface velocities as functions of time.

A signal is built from primitives (`constant`, `step`, `ramp`, `sine`, `table`) and ``+``,
``-``, ``*`` between signals and numbers. It is evaluated by the library (Fortran module
``stickslip_signal``), never by a call back into Python; a step's time, a ramp's start and
end and a table's points are corners where the methods with events (``event_driven``)
restart.

Examples
--------
>>> import stickslip as ss
>>> S = ss.signal
>>> clutch = 20.0 * S.step(0.4)                        # 0 N, then 20 N from t = 0.4 s
>>> drive = S.sine(10.0, 5.0) + S.ramp(0.0, 1.0, 2.0)  # 10 sin(2 pi 5 t) + a ramp to 2
>>> clutch.to_dict()
{'mul': [{'constant': 20.0}, {'step': {'time': 0.4, 'before': 0.0, 'after': 1.0}}]}
"""
from __future__ import annotations

import math
from typing import Any, Union

import numpy as np

__all__ = ["Signal", "constant", "step", "ramp", "sine", "table", "as_signal"]

#: Operation codes of the library's signal programs (stickslip_signal's SIG_*).
_OPS = {"constant": 1, "step": 2, "ramp": 3, "sine": 4, "table": 5, "add": 6, "sub": 7, "mul": 8}
#: The arguments of each primitive, in the library's order.
_ARGS = {"constant": ("value",), "step": ("time", "before", "after"),
         "ramp": ("start", "duration", "height"), "sine": ("amplitude", "frequency", "phase", "offset")}


def _real(kind: str, name: str, value: Any) -> float:
    """A finite real number, or ValueError naming the signal's argument."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{kind}: {name} must be a finite real number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{kind}: {name} must be finite, got {value!r}")
    return value


class Signal:
    """A function of time, built from primitives and ``+``, ``-``, ``*`` (see the module).

    Signals are immutable; combining them makes a new one. Use the functions `constant`,
    `step`, `ramp`, `sine` and `table` to make them.
    """

    __slots__ = ("kind", "args", "children")

    def __init__(self, kind: str, args: tuple[Any, ...] = (), children: tuple["Signal", ...] = ()) -> None:
        self.kind, self.args, self.children = kind, args, children

    # -- arithmetic ----------------------------------------------------------------
    def _combine(self, other: Any, op: str, swap: bool = False) -> "Signal":
        o = as_signal(other, "operand")
        return Signal(op, (), (o, self) if swap else (self, o))

    def __add__(self, other: Any) -> "Signal":
        return self._combine(other, "add")

    def __radd__(self, other: Any) -> "Signal":
        return self._combine(other, "add", swap=True)

    def __sub__(self, other: Any) -> "Signal":
        return self._combine(other, "sub")

    def __rsub__(self, other: Any) -> "Signal":
        return self._combine(other, "sub", swap=True)

    def __mul__(self, other: Any) -> "Signal":
        return self._combine(other, "mul")

    def __rmul__(self, other: Any) -> "Signal":
        return self._combine(other, "mul", swap=True)

    def __neg__(self) -> "Signal":
        return Signal("mul", (), (constant(-1.0), self))

    # -- what the library reads ------------------------------------------------------
    def program(self, tables: list[float], values: list[float]) -> list[tuple[int, tuple[float, ...]]]:
        """The postfix program of this signal: (operation code, 4 arguments) per operation;
        a table's points are appended to `tables` and `values` (its arguments give where)."""
        if self.kind in ("add", "sub", "mul"):
            return (self.children[0].program(tables, values) + self.children[1].program(tables, values)
                    + [(_OPS[self.kind], (0.0, 0.0, 0.0, 0.0))])
        if self.kind == "table":
            t, v = self.args
            first = len(tables) + 1
            tables.extend(t)
            values.extend(v)
            return [(_OPS["table"], (float(first), float(len(t)), 0.0, 0.0))]
        return [(_OPS[self.kind], tuple(self.args) + (0.0,) * (4 - len(self.args)))]

    def bounds(self) -> tuple[float, float]:
        """Bounds (low, high) on the signal's values over all times, by interval arithmetic
        over its parts (exact for a primitive; a sum's or a product's may be wider than the
        signal's own range)."""
        if self.kind in ("add", "sub", "mul"):
            (a, b), (c, d) = (child.bounds() for child in self.children)
            if self.kind == "add":
                return a + c, b + d
            if self.kind == "sub":
                return a - d, b - c
            products = (a * c, a * d, b * c, b * d)
            return min(products), max(products)
        if self.kind == "constant":
            return self.args[0], self.args[0]
        if self.kind == "step":
            return min(self.args[1], self.args[2]), max(self.args[1], self.args[2])
        if self.kind == "ramp":
            return min(0.0, self.args[2]), max(0.0, self.args[2])
        if self.kind == "sine":
            amplitude, offset = abs(self.args[0]), self.args[3]
            return offset - amplitude, offset + amplitude
        values = self.args[1]                               # a table
        return min(values), max(values)

    def to_dict(self) -> Any:
        """The signal as plain data (a number, or a one-key dict), as a TOML model file holds it."""
        if self.kind == "constant":
            return {"constant": self.args[0]}
        if self.kind in ("add", "sub", "mul"):
            return {self.kind: [c.to_dict() for c in self.children]}
        if self.kind == "table":
            return {"table": {"t": list(self.args[0]), "values": list(self.args[1])}}
        return {self.kind: dict(zip(_ARGS[self.kind], self.args))}

    @classmethod
    def from_dict(cls, data: Any, where: str = "signal") -> "Signal":
        """The inverse of `to_dict` (also takes a plain number); ValueError naming `where`."""
        if not isinstance(data, dict):
            return as_signal(data, where)
        if len(data) != 1:
            raise ValueError(f"{where}: a signal is a number or a table with one key "
                             f"({', '.join(_OPS)}), got {data!r}")
        (kind, body), = data.items()
        if kind in ("add", "sub", "mul"):
            if not isinstance(body, list) or len(body) != 2:
                raise ValueError(f"{where}: {kind} takes a list of two signals, got {body!r}")
            return Signal(kind, (), tuple(cls.from_dict(b, where) for b in body))
        if kind == "constant":
            return constant(body)
        if kind == "table":
            if not isinstance(body, dict) or set(body) != {"t", "values"}:
                raise ValueError(f"{where}: table takes t and values, got {body!r}")
            return table(body["t"], body["values"])
        if kind not in _ARGS or not isinstance(body, dict):
            raise ValueError(f"{where}: unknown signal {kind!r} (accepted: {', '.join(_OPS)})")
        unknown = set(body) - set(_ARGS[kind])
        if unknown:
            raise ValueError(f"{where}: {kind} has no argument(s) {', '.join(sorted(unknown))} "
                             f"(its arguments: {', '.join(_ARGS[kind])})")
        return {"step": step, "ramp": ramp, "sine": sine}[kind](**body)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Signal) and self.to_dict() == other.to_dict()

    def __hash__(self) -> int:
        return hash(repr(self.to_dict()))

    def __repr__(self) -> str:
        return f"Signal({self.to_dict()!r})"


SignalLike = Union[Signal, float, int]


def as_signal(value: Any, name: str = "signal") -> Signal:
    """A signal as it is, a number as a `constant`; ValueError naming `name` otherwise."""
    if isinstance(value, Signal):
        return value
    return constant(_real("constant", name, value))


def constant(value: float) -> Signal:
    """The signal that is `value` at every time."""
    return Signal("constant", (_real("constant", "value", value),))


def step(time: float, before: float = 0.0, after: float = 1.0) -> Signal:
    """`before` up to `time` [s], `after` from `time` on (right-continuous)."""
    return Signal("step", (_real("step", "time", time), _real("step", "before", before),
                           _real("step", "after", after)))


def ramp(start: float, duration: float, height: float) -> Signal:
    """0 before `start` [s], rising linearly to `height` over `duration` [s] (> 0), then `height`."""
    d = _real("ramp", "duration", duration)
    if not d > 0.0:
        raise ValueError(f"ramp: duration must be > 0 [s], got {duration!r}")
    return Signal("ramp", (_real("ramp", "start", start), d, _real("ramp", "height", height)))


def sine(amplitude: float, frequency: float, phase: float = 0.0, offset: float = 0.0) -> Signal:
    """amplitude sin(2 pi frequency t + phase) + offset; frequency in Hz, phase in rad."""
    return Signal("sine", (_real("sine", "amplitude", amplitude), _real("sine", "frequency", frequency),
                           _real("sine", "phase", phase), _real("sine", "offset", offset)))


def table(t: Any, values: Any) -> Signal:
    """Linear between the points (t [s], strictly increasing; values), held constant outside."""
    try:
        tt = np.asarray(t, dtype=np.float64).ravel()
        vv = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise ValueError("table: t and values must be sequences of real numbers") from None
    if tt.size < 1 or tt.size != vv.size:
        raise ValueError(f"table: t and values must be non-empty and of one length, got {tt.size} and {vv.size}")
    if not (np.isfinite(tt).all() and np.isfinite(vv).all()):
        raise ValueError("table: t and values must be finite")
    if np.any(np.diff(tt) <= 0.0):
        raise ValueError("table: t must be strictly increasing [s]")
    return Signal("table", (tuple(tt.tolist()), tuple(vv.tolist())))
