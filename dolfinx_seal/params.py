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
import difflib
import functools
import math
import numbers
import re
import sys
import tomllib
import types
import typing
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

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
def interval_text(
    lo: float = -math.inf, hi: float = math.inf, lo_open: bool = False, hi_open: bool = False
) -> str:
    """``(0, inf)``, ``[1, 4]``, ...: the interval of a range check as error messages show it."""
    left = "(" if lo_open or lo == -math.inf else "["
    right = ")" if hi_open or hi == math.inf else "]"
    return f"{left}{lo:g}, {hi:g}{right}"


def _is_real(value: Any) -> bool:
    """A real number (Python, numpy scalar or 0-d array), not a bool, a string or a container."""
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and np.issubdtype(value.dtype, np.number) and value.dtype.kind != "c"
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def check_finite(name: str, value: float, allowed: str = "") -> float:
    """Raise :class:`ParameterError` unless ``value`` is a finite real number.

    ``allowed`` (e.g. ``"(0, inf) m"``) is appended to the message.
    """
    tail = f" (allowed range {allowed})" if allowed else ""
    if not _is_real(value):
        raise ParameterError(f"{name} must be a real number, got {value!r}{tail}", name)
    v = float(value)
    if not math.isfinite(v):
        raise ParameterError(f"{name} must be finite, got {value!r}{tail}", name)
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
    ``nu = 0.6 is outside the allowed range (-1, 0.5]``; a value that is not a
    finite real number (``nan``, ``inf``, a string) gets the interval too.
    """
    rng = interval_text(lo, hi, lo_open, hi_open)
    u = f" {unit}" if unit else ""
    v = check_finite(name, value, rng + u)
    bad = (v < lo or (lo_open and v == lo)) or (v > hi or (hi_open and v == hi))
    if bad:
        raise ParameterError(f"{name} = {value!r}{u} is outside the allowed range {rng}", name)
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
    try:
        ok = value in choices
    except TypeError:  # an unhashable value against a set-like
        ok = False
    if not ok:
        raise ParameterError(
            f"{name} = {value!r} is not one of {', '.join(map(repr, choices))}", name
        )
    _record(name, value, "choice", choices=choices)
    return value


def check_int_range(name: str, value: int, lo: int, hi: int | None = None) -> int:
    """Check an integer ``lo <= value <= hi``."""
    rng = f"[{lo}, {hi}]" if hi is not None else f"[{lo}, inf)"
    if not _is_real(value) or not math.isfinite(value) or int(value) != value:
        raise ParameterError(
            f"{name} must be an integer, got {value!r} (allowed range {rng})", name
        )
    v = int(value)
    if v < lo or (hi is not None and v > hi):
        raise ParameterError(f"{name} = {value!r} is outside the allowed range {rng}", name)
    _record(name, value, "integer", lo=lo, hi=math.inf if hi is None else hi)
    return v


def check_bool(name: str, value: Any) -> bool:
    """Check that ``value`` is ``True`` or ``False`` (a string such as ``"no"`` is not)."""
    if not isinstance(value, bool | np.bool_):
        raise ParameterError(f"{name} must be true or false, got {value!r}", name)
    return bool(value)


def check_types(obj: Any, prefix: str = "") -> None:
    """Check the kind of every field of parameter dataclass ``obj`` (recursively).

    The range checks of ``__post_init__`` see numbers; this catches what they do
    not when parameters are built directly in Python (``lubricated="no"``, a
    table of the wrong class, ``model=3``): bools must be bools, strings strings,
    nested tables instances of their class.  Numbers are left to the range checks
    (which refuse a bool or a string, quoting the allowed range).
    """
    for name, tp in _field_types(type(obj)).items():
        value = getattr(obj, name)
        full = f"{prefix}{name}"
        if _is_dataclass_type(tp):
            if not isinstance(value, tp):
                raise ParameterError(
                    f"{full} must be a {tp.__name__} table of parameters, got {value!r}", full
                )
            check_types(value, f"{full}.")
        elif tp is bool:
            check_bool(full, value)
        elif tp is str and not isinstance(value, str):
            raise ParameterError(f"{full} must be a string, got {value!r}", full)


# ---------------------------------------------------- dataclasses <-> mappings
@functools.cache
def _field_types(cls: type) -> dict[str, Any]:
    """``name -> annotated type`` of the init fields of dataclass ``cls`` (do not modify)."""
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
        raise ParameterError(f"{name}: cannot interpret {value!r} ({'; '.join(errors)})", name)
    if origin is typing.Literal:
        return check_choice(name, value, args)
    if isinstance(value, Mapping):
        raise ParameterError(f"{name} is a value, not a table: got {dict(value)!r}", name)
    if origin in (tuple, list):
        if isinstance(value, str):  # "1,2", "(1, 2)" or "[1, 2]"
            value = [s for s in re.sub(r"[()\[\]]", "", value).split(",") if s.strip()]
        if not isinstance(value, list | tuple):
            raise ParameterError(f"{name} must be a list, got {value!r}", name)
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
        raise ParameterError(f"{name} must be true or false, got {value!r}", name)
    if tp is int:
        f = _number(name, value, "an integer")
        if not math.isfinite(f) or f != int(f):
            raise ParameterError(f"{name} must be an integer, got {value!r}", name)
        return int(f)
    if tp is float:
        return _number(name, value, "a number")
    if tp is str:
        if isinstance(value, list | tuple | dict):
            raise ParameterError(f"{name} must be a string, got {value!r}", name)
        return str(value)
    if tp is Path:
        if not isinstance(value, str | Path):
            raise ParameterError(f"{name} must be a path, got {value!r}", name)
        return Path(value)
    return value


def _number(name: str, value: Any, kind: str) -> float:
    """``float(value)`` for a number or a numeric string (not a bool)."""
    if isinstance(value, bool) or not isinstance(value, str | numbers.Real):
        raise ParameterError(f"{name} must be {kind}, got {value!r}", name)
    try:
        return float(value)
    except ValueError:
        raise ParameterError(f"{name} must be {kind}, got {value!r}", name) from None


def _allowed_text(cls: type, base: Any, key: str) -> str:
    """What the checks of ``cls`` allow for field ``key`` (read off a default
    instance, as ``dolfinx-seal params`` does), e.g. ``"(0, inf) m"``; "" if unchecked."""
    try:
        with recording_checks() as records:
            obj = dataclasses.replace(base) if base is not None else cls()
    except Exception:  # a class without complete defaults: nothing to read
        return ""
    for r in records:
        if not any(o is obj for o in r.owners):
            continue
        if r.name != key and not r.name.endswith("." + key):
            continue
        if r.kind == "choice":
            return "one of " + ", ".join(map(repr, r.choices))
        if r.kind == "integer":
            hi = "inf)" if r.hi == math.inf else f"{r.hi:g}]"
            return f"integer in [{r.lo:g}, {hi}"
        u = f" {r.unit}" if r.unit else ""
        return interval_text(r.lo, r.hi, r.lo_open, r.hi_open) + u
    return ""


def _unknown_key(full: str, key: Any, value: Any, allowed: Iterable[str]) -> ParameterError:
    """The error for an unknown key, suggesting the nearest allowed name."""
    allowed = sorted(allowed)
    near = difflib.get_close_matches(str(key), allowed, n=1, cutoff=0.6)
    hint = f" (did you mean {full[: len(full) - len(str(key))] + near[0]!r}?)" if near else ""
    where = f" of {full.rsplit('.', 1)[0]}" if "." in full else ""
    return ParameterError(
        f"unknown parameter {full!r}{'' if value is None else f' = {value!r}'}{hint}; "
        f"the names allowed{where} are: "
        f"{', '.join(allowed)}",
        full,
    )


def from_mapping(cls: type[T], data: Mapping[str, Any], prefix: str = "", base: Any = None) -> T:
    """Build dataclass ``cls`` from a (nested) mapping; unknown keys are an error.

    Nested dataclass fields take nested mappings (TOML tables).  A nested table
    changes only the keys it names: the others keep the enclosing class's default
    for that field (e.g. the ball's ``film.speed = 0.01`` survives
    ``--set film.viscosity=0.05``), or those of ``base`` when given.  A name
    that ``cls`` has renamed is refused with the new one (:func:`refuse_renamed`).

    Every :class:`ParameterError` raised while building a nested table names the
    parameter in full (``material.nu``, ``lip.interference``): the checks inside
    a nested class see only its own field names, and the message is rewritten
    here with the table's prefix.  A value that cannot be converted (``radius =
    "abc"``) gets the allowed range of the field in the message.
    """
    if not isinstance(data, Mapping):
        where = prefix[:-1] or "parameters"
        raise ParameterError(f"{where} must be a table of parameters, got {data!r}", where or None)
    refuse_renamed(cls, data, prefix)
    types_ = _field_types(cls)
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        full = f"{prefix}{key}"
        if key not in types_:
            raise _unknown_key(full, key, value, types_)
        tp = types_[key]
        if _is_dataclass_type(tp):
            if not isinstance(value, Mapping):
                raise ParameterError(
                    f"{full} is a table of parameters ({', '.join(sorted(_field_types(tp)))}), "
                    f"not a value: got {value!r}",
                    full,
                )
            inner = getattr(base, key) if base is not None else _field_default(cls, key)
            kwargs[key] = from_mapping(tp, value, prefix=f"{full}.", base=inner)
        else:
            try:
                kwargs[key] = _coerce(full, tp, value)
            except ParameterError as e:
                allowed = _allowed_text(cls, base, key)
                if not allowed:
                    raise
                raise ParameterError(f"{e} (allowed: {allowed})", full) from None
    try:
        if base is not None:
            return dataclasses.replace(base, **kwargs)
        return cls(**kwargs)
    except ParameterError as e:
        if not prefix:
            raise
        raise _dotted_error(e, cls, prefix) from None


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


def _dotted_error(e: ParameterError, cls: type, prefix: str) -> ParameterError:
    """Error ``e`` of a check inside nested dataclass ``cls`` at ``prefix``, with the
    parameter it is about spelled in full (``interference = ...`` under ``lip.``
    becomes ``lip.interference = ...``; ``roughness.h_rms`` under
    ``lip.roughness.`` becomes ``lip.roughness.h_rms``), and the other fields of
    ``cls`` the message quotes (``... needs formulation = 'mixed'``) too."""
    msg = str(e)
    fields = {f.name for f in dataclasses.fields(cls)}
    owner = prefix[:-1].rsplit(".", 1)[-1]
    parent = prefix[: -len(owner) - 1]

    def full(name: str) -> str | None:
        if name.startswith(prefix):
            return name
        head = name.split(".", 1)[0]
        if "." in name and head == owner:  # the check names itself "table.field"
            return parent + name
        if head in fields:
            return prefix + name
        return None

    param = e.parameter or msg.split(" ", 1)[0]
    new = full(param)
    if new is not None and msg.startswith(param):
        msg = new + msg[len(param) :]

    def sub(m: re.Match[str]) -> str:
        return full(m.group(1)) or m.group(1)

    # other fields quoted as "name = value" later in the message
    head_len = len(new or param) if msg.startswith(new or param) else 0
    rest = re.sub(r"(?<![\w.'\"])([A-Za-z_]\w*(?:\.\w+)*)(?= = )", sub, msg[head_len:])
    return ParameterError(msg[:head_len] + rest, new or e.parameter)


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
        if not isinstance(item, str) or "=" not in item:
            raise ParameterError(f"--set expects key=value, got {item!r}")
        key, value = item.split("=", 1)
        parts = key.strip().split(".")
        if not all(re.fullmatch(r"[A-Za-z_][\w-]*", p) for p in parts):
            raise ParameterError(
                f"--set {item!r}: {key.strip()!r} is not a (dotted) parameter name"
            )
        node = out
        for i, p in enumerate(parts[:-1]):
            node = node.setdefault(p, {})
            if not isinstance(node, dict):
                raise ParameterError(
                    f"--set {key}: {'.'.join(parts[: i + 1])!r} is given a value and a table",
                    ".".join(parts[: i + 1]),
                )
        if isinstance(node.get(parts[-1]), dict):
            raise ParameterError(
                f"--set {key}: {key.strip()!r} is given a value and a table", key.strip()
            )
        node[parts[-1]] = value.strip()
    return out


def flatten(d: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """Nested tables to dotted keys (``{"material": {"E": 1}}`` -> ``{"material.E": 1}``)."""
    out: dict[str, Any] = {}
    for k, v in d.items():
        name = f"{prefix}{k}"
        if isinstance(v, Mapping):
            out.update(flatten(v, name + "."))
        else:
            out[name] = v
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
    """Read a TOML scene file into a mapping (the optional ``scene`` key is kept).

    A missing, unreadable or malformed file, or a ``parameters`` entry that is
    not a table, is a :class:`ParameterError` naming the file (and, for a syntax
    error, the line and column).
    """
    p = Path(path)
    if not p.exists():
        raise ParameterError(f"scene file {str(p)!r} does not exist")
    if not p.is_file():
        raise ParameterError(f"scene file {str(p)!r} is not a file")
    try:
        with p.open("rb") as fh:
            data = tomllib.load(fh)
    except OSError as e:
        raise ParameterError(f"scene file {str(p)!r} cannot be read: {e.strerror or e}") from None
    except tomllib.TOMLDecodeError as e:
        raise ParameterError(f"scene file {str(p)!r} is not valid TOML: {e}") from None
    except UnicodeDecodeError as e:
        raise ParameterError(f"scene file {str(p)!r} is not UTF-8 text: {e}") from None
    if "scene" in data and not isinstance(data["scene"], str):
        raise ParameterError(
            f"scene file {str(p)!r}: scene = {data['scene']!r} must be a scene name", "scene"
        )
    if "parameters" in data and not isinstance(data["parameters"], dict):
        raise ParameterError(
            f"scene file {str(p)!r}: parameters = {data['parameters']!r} must be a table "
            "([parameters])",
            "parameters",
        )
    return data


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
    """A copy of ``parameters`` with ``dotted`` (e.g. ``roughness.h_rms``) set to ``value``.

    Validated as ``--set dotted=value`` is: errors name the full dotted parameter;
    a renamed name is refused with the new one.
    """
    refuse_renamed(type(parameters), {dotted: value})
    parts = str(dotted).split(".")
    node: Any = parameters
    for i, part in enumerate(parts):
        fields = _field_types(type(node)) if dataclasses.is_dataclass(node) else {}
        here = ".".join(parts[: i + 1])
        if part not in fields:
            raise _unknown_key(here, part, value, fields)
        node = getattr(node, part)
    if dataclasses.is_dataclass(node):
        names = list(_field_types(type(node)))
        raise ParameterError(
            f"{dotted} is a table of parameters ({', '.join(sorted(names))}), "
            f"not a value: name one of them, e.g. {dotted}.{names[0]}",
            dotted,
        )
    data: Any = value
    for part in reversed(parts):
        data = {part: data}
    return from_mapping(type(parameters), data, base=parameters)
