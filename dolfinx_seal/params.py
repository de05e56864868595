"""Parameters: validation helpers and the dataclass <-> dict/TOML/CLI bridge.

Each concept (a material, a roughness, a scene) has one small dataclass whose
field defaults are the single source of defaults for the Python API, TOML scene
files and the ``--set key=value`` overrides of the CLI.  This module turns
mappings and ``key=value`` strings into those dataclasses, rejecting unknown
keys, and offers the range checks the dataclasses call in ``__post_init__``.

The checks are also the single source of the allowed ranges that
``dolfinx-seal params`` and ``docs/parameters.md`` show: inside
:func:`recording_checks`, every check that passes is recorded together with the
dataclass instances whose ``__post_init__`` is running
(:mod:`dolfinx_seal.paramdoc` maps the records to dotted parameter names).

All values are SI.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import tomllib
import types
import typing
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

from dolfinx_seal.errors import ParameterError

T = TypeVar("T")


# ------------------------------------------------------- recording the checks
@dataclass(frozen=True)
class CheckRecord:
    """One check that passed while :func:`recording_checks` was active.

    Attributes:
        name: The name the check was called with (e.g. ``"film.speed"``, ``"E"``).
        value: The value checked.
        kind: ``"range"`` (real interval), ``"integer"`` (integer interval) or ``"choice"``.
        lo, hi: Bounds of the interval (``-inf`` / ``inf`` when open-ended).
        lo_open, hi_open: Whether a bound is excluded.
        unit: The unit text the check was given (e.g. ``"m (<= a_Hertz/4)"``), or "".
        choices: The allowed values of a ``"choice"`` check.
        owners: The dataclass instances whose ``__post_init__`` was running when the
            check was called, innermost first.
    """

    name: str
    value: Any
    kind: str
    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    choices: tuple[Any, ...] = ()
    owners: tuple[Any, ...] = ()


_RECORDERS: list[list[CheckRecord]] = []


@contextmanager
def recording_checks() -> Iterator[list[CheckRecord]]:
    """Collect a :class:`CheckRecord` for every check that passes inside the block.

    Used to read the allowed ranges off the checks themselves (construct the
    parameters inside the block), so documented ranges cannot drift from the
    enforced ones.  Recording costs nothing outside such a block.
    """
    records: list[CheckRecord] = []
    _RECORDERS.append(records)
    try:
        yield records
    finally:
        _RECORDERS.remove(records)


def _validating_instances() -> tuple[Any, ...]:
    """Dataclass instances whose ``__post_init__`` is on the call stack, innermost first."""
    out = []
    frame = sys._getframe(1)
    while frame is not None:
        if frame.f_code.co_name == "__post_init__":
            obj = frame.f_locals.get("self")
            if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
                out.append(obj)
        frame = frame.f_back
    return tuple(out)


def _record(name: str, value: Any, kind: str, **kw: Any) -> None:
    if not _RECORDERS:
        return
    r = CheckRecord(name=name, value=value, kind=kind, owners=_validating_instances(), **kw)
    for records in _RECORDERS:
        records.append(r)


# --------------------------------------------------------------------- checks
def check_finite(name: str, value: float) -> float:
    """Raise :class:`ParameterError` unless ``value`` is a finite real number."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a real number, got {value!r}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite, got {value!r}")
    return v


def check_range(
    name: str,
    value: float,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> float:
    """Check ``lo <= value <= hi`` (strict where ``*_open``) and return ``float(value)``.

    The error names the parameter, the value and the allowed interval, e.g.
    ``nu = 0.6 is outside the allowed range (-1, 0.5)``.
    """
    v = check_finite(name, value)
    bad = (v < lo or (lo_open and v == lo)) or (v > hi or (hi_open and v == hi))
    if bad:
        left = "(" if lo_open or lo == -math.inf else "["
        right = ")" if hi_open or hi == math.inf else "]"
        u = f" {unit}" if unit else ""
        raise ParameterError(
            f"{name} = {value!r}{u} is outside the allowed range {left}{lo:g}, {hi:g}{right}"
        )
    _record(name, value, "range", lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
    return v


def check_positive(name: str, value: float, unit: str = "") -> float:
    """Check ``value > 0``."""
    return check_range(name, value, 0.0, math.inf, lo_open=True, unit=unit)


def check_nonnegative(name: str, value: float, unit: str = "") -> float:
    """Check ``value >= 0``."""
    return check_range(name, value, 0.0, math.inf, unit=unit)


def check_choice(name: str, value: str, choices: Iterable[str]) -> str:
    """Check that ``value`` is one of ``choices``."""
    choices = tuple(choices)
    if value not in choices:
        raise ParameterError(f"{name} = {value!r} is not one of {', '.join(map(repr, choices))}")
    _record(name, value, "choice", choices=choices)
    return value


def check_int_range(name: str, value: int, lo: int, hi: int | None = None) -> int:
    """Check an integer ``lo <= value <= hi``."""
    if isinstance(value, bool) or not isinstance(value, int | float) or int(value) != value:
        raise ParameterError(f"{name} must be an integer, got {value!r}")
    v = int(value)
    if v < lo or (hi is not None and v > hi):
        rng = f"[{lo}, {hi}]" if hi is not None else f"[{lo}, inf)"
        raise ParameterError(f"{name} = {value!r} is outside the allowed range {rng}")
    _record(name, value, "integer", lo=lo, hi=math.inf if hi is None else hi)
    return v


# ---------------------------------------------------- dataclasses <-> mappings
def _field_types(cls: type) -> dict[str, Any]:
    hints = typing.get_type_hints(cls)
    return {f.name: hints[f.name] for f in dataclasses.fields(cls) if f.init}


def _is_dataclass_type(tp: Any) -> bool:
    return isinstance(tp, type) and dataclasses.is_dataclass(tp)


def _coerce(name: str, tp: Any, value: Any) -> Any:
    """Convert ``value`` (possibly a string from the CLI) to the annotated type ``tp``."""
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if origin in (typing.Union, types.UnionType):
        if value is None or (isinstance(value, str) and value.lower() in ("none", "null")):
            if type(None) in args:
                return None
        errors = []
        for a in args:
            if a is type(None):
                continue
            try:
                return _coerce(name, a, value)
            except ParameterError as e:
                errors.append(str(e))
        raise ParameterError(f"{name}: cannot interpret {value!r} ({'; '.join(errors)})")
    if origin is typing.Literal:
        v = value
        if v not in args:
            raise ParameterError(f"{name} = {value!r} is not one of {', '.join(map(repr, args))}")
        return v
    if origin in (tuple, list):
        if isinstance(value, str):
            value = [s for s in value.replace("(", "").replace(")", "").split(",") if s.strip()]
        if not isinstance(value, list | tuple):
            raise ParameterError(f"{name} must be a list, got {value!r}")
        item = args[0] if args else Any
        out = [_coerce(name, item, v) for v in value]
        return tuple(out) if origin is tuple else out
    if tp is bool:
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.lower() in ("1", "true", "yes", "on"):
            return True
        if isinstance(value, str) and value.lower() in ("0", "false", "no", "off"):
            return False
        raise ParameterError(f"{name} must be true or false, got {value!r}")
    if tp is int:
        try:
            f = float(value)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} must be an integer, got {value!r}") from None
        if f != int(f):
            raise ParameterError(f"{name} must be an integer, got {value!r}")
        return int(f)
    if tp is float:
        if isinstance(value, bool):
            raise ParameterError(f"{name} must be a number, got {value!r}")
        try:
            return float(value)
        except (TypeError, ValueError):
            raise ParameterError(f"{name} must be a number, got {value!r}") from None
    if tp is str:
        return str(value)
    if tp is Path:
        return Path(value)
    return value


def from_mapping(cls: type[T], data: Mapping[str, Any], prefix: str = "", base: Any = None) -> T:
    """Build dataclass ``cls`` from a (nested) mapping; unknown keys are an error.

    Nested dataclass fields take nested mappings (TOML tables).  A nested table
    changes only the keys it names: the others keep the enclosing class's default
    for that field (e.g. the ball's ``film.speed = 0.01`` survives
    ``--set film.viscosity=0.05``), or those of ``base`` when given.  A name
    that ``cls`` has renamed is refused with the new one (:func:`refuse_renamed`).
    """
    refuse_renamed(cls, data, prefix)
    types_ = _field_types(cls)
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        full = f"{prefix}{key}"
        if key not in types_:
            raise ParameterError(
                f"unknown parameter {full!r}; allowed: {', '.join(sorted(types_))}"
            )
        tp = types_[key]
        if _is_dataclass_type(tp):
            if not isinstance(value, Mapping):
                raise ParameterError(f"{full} must be a table of parameters, got {value!r}")
            inner = getattr(base, key) if base is not None else _field_default(cls, key)
            kwargs[key] = from_mapping(tp, value, prefix=f"{full}.", base=inner)
        else:
            kwargs[key] = _coerce(full, tp, value)
    try:
        if base is not None:
            return dataclasses.replace(base, **kwargs)
        return cls(**kwargs)
    except ParameterError as e:
        if not prefix:
            raise
        raise ParameterError(_dotted_message(str(e), cls, prefix)) from None


def refuse_renamed(cls: type, data: Mapping[str, Any], prefix: str = "") -> None:
    """Refuse a parameter of ``data`` that dataclass ``cls`` no longer takes, naming its new name.

    ``cls`` lists its old names in the class attribute ``RENAMED`` (a ``ClassVar``):
    ``{old: new}`` or ``{old: (new, unit)}``, dotted names relative to ``cls``; the
    unit (or the allowed values, or a conversion rule) is shown in brackets.  An
    old table renames every parameter under it (``"modulus": "material"`` sends
    ``modulus.tau`` to ``material.tau``) unless a longer old name matches
    (``"modulus.kind": "material.model"``).  A name that is a parameter of ``cls``
    is never refused, so an old plain parameter may become a table of the same
    name (``contact = "exact"`` refused for ``contact.model``, ``[contact]``
    tables accepted).  Keys of ``data`` may be nested mappings or dotted strings;
    ``prefix`` (the dotted path of ``cls``) is prepended to the names shown.

    Raises:
        ParameterError: e.g. ``'velocity' was renamed: use 'film.speed' [m/s]``.
    """
    renamed: Mapping[str, str | tuple[str, str]] = getattr(cls, "RENAMED", None) or {}
    if not renamed:
        return

    def leaves(node: Mapping[str, Any], head: str) -> Iterator[tuple[str, Any]]:
        for key, value in node.items():
            name = f"{head}{key}"
            if isinstance(value, Mapping) and value:
                yield from leaves(value, f"{name}.")
            else:
                yield name, value

    def is_parameter(name: str, value: Any) -> bool:
        """``name`` is a parameter of ``cls`` (a table if ``value`` is an empty one)."""
        tp: Any = cls
        for part in name.split("."):
            if not _is_dataclass_type(tp) or part not in (types_ := _field_types(tp)):
                return False
            tp = types_[part]
        return _is_dataclass_type(tp) == isinstance(value, Mapping)

    for name, value in leaves(data, ""):
        if is_parameter(name, value):
            continue
        parts = name.split(".")
        for n in range(len(parts), 0, -1):  # the longest old name first
            old = ".".join(parts[:n])
            if old in renamed:
                entry = renamed[old]
                new, unit = (entry, "") if isinstance(entry, str) else entry
                new_name = ".".join([new, *parts[n:]])
                note = f" [{unit}]" if unit else ""
                raise ParameterError(
                    f"'{prefix}{name}' was renamed: use '{prefix}{new_name}'{note}"
                )


def _dotted_message(msg: str, cls: type, prefix: str) -> str:
    """``msg`` of a check inside nested dataclass ``cls`` at ``prefix``, with the
    parameter it starts with spelled in full (``interference = ...`` under
    ``lip.`` becomes ``lip.interference = ...``; ``roughness.h_rms`` under
    ``lip.roughness.`` becomes ``lip.roughness.h_rms``)."""
    token = msg.split(" ", 1)[0]
    if token.startswith(prefix):
        return msg
    head = token.split(".", 1)[0]
    owner = prefix[:-1].rsplit(".", 1)[-1]
    if "." in token and head == owner:  # the check names itself "table.field"
        return prefix[: -len(owner) - 1] + msg
    if head in {f.name for f in dataclasses.fields(cls)}:
        return prefix + msg
    return msg


def _field_default(cls: type, name: str) -> Any:
    """The default value of field ``name`` of ``cls`` (None if it has none)."""
    f = {f.name: f for f in dataclasses.fields(cls)}[name]
    if f.default_factory is not dataclasses.MISSING:
        return f.default_factory()
    return None if f.default is dataclasses.MISSING else f.default


def to_dict(obj: Any) -> dict[str, Any]:
    """Nested dict of a parameter dataclass (paths as strings), for ``results.json``."""

    def conv(v: Any) -> Any:
        if dataclasses.is_dataclass(v) and not isinstance(v, type):
            return {f.name: conv(getattr(v, f.name)) for f in dataclasses.fields(v)}
        if isinstance(v, Path):
            return str(v)
        if isinstance(v, tuple | list):
            return [conv(x) for x in v]
        return v

    return conv(obj)


def parse_overrides(items: Iterable[str]) -> dict[str, Any]:
    """Turn ``["a=1", "b.c=x"]`` into the nested mapping ``{"a": "1", "b": {"c": "x"}}``."""
    out: dict[str, Any] = {}
    for item in items:
        if "=" not in item:
            raise ParameterError(f"--set expects key=value, got {item!r}")
        key, value = item.split("=", 1)
        parts = key.strip().split(".")
        node = out
        for p in parts[:-1]:
            node = node.setdefault(p, {})
            if not isinstance(node, dict):
                raise ParameterError(f"--set {key}: {p!r} is not a table")
        node[parts[-1]] = value.strip()
    return out


def merge(base: Mapping[str, Any], over: Mapping[str, Any]) -> dict[str, Any]:
    """Recursive merge of two nested mappings (``over`` wins)."""
    out = dict(base)
    for k, v in over.items():
        if isinstance(v, Mapping) and isinstance(out.get(k), Mapping):
            out[k] = merge(out[k], v)
        else:
            out[k] = v
    return out


def load_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML scene file into a mapping (the optional ``scene`` key is kept)."""
    p = Path(path)
    if not p.is_file():
        raise ParameterError(f"scene file {str(p)!r} does not exist")
    with p.open("rb") as fh:
        return tomllib.load(fh)


def replace(obj: T, **changes: Any) -> T:
    """``dataclasses.replace`` that re-runs validation (``__post_init__``)."""
    return dataclasses.replace(obj, **changes)  # type: ignore[type-var]


def get_dotted(parameters: Any, dotted: str) -> Any:
    """The value of ``dotted`` in ``parameters`` (``None`` where a name is unknown)."""
    obj = parameters
    for part in dotted.split("."):
        if not (
            dataclasses.is_dataclass(obj) and part in {f.name for f in dataclasses.fields(obj)}
        ):
            return None
        obj = getattr(obj, part)
    return obj


def set_parameter(parameters: Any, dotted: str, value: Any) -> Any:
    """A copy of ``parameters`` with ``dotted`` (e.g. ``roughness.h_rms``) set to ``value``."""
    refuse_renamed(type(parameters), {dotted: value})
    head, _, rest = dotted.partition(".")
    fields = {f.name: f for f in dataclasses.fields(parameters)}
    if head not in fields:
        raise ParameterError(f"unknown parameter {dotted!r}; allowed: {', '.join(sorted(fields))}")
    if rest:
        inner = set_parameter(getattr(parameters, head), rest, value)
        return dataclasses.replace(parameters, **{head: inner})
    data = to_dict(parameters)
    data[head] = value
    return from_mapping(type(parameters), data)
