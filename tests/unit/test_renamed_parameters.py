"""Renamed parameters are refused with their new name (``params.refuse_renamed``).

The pure-numpy scenes took their own names for quantities the FEM scenes call
``film.speed``, ``material.E``, ``roughness.q1``, ...; the old names are listed in
each scene's ``RENAMED`` and must be refused, naming the new one, wherever a
parameter can be given: a TOML scene file, ``--set`` on the CLI, ``--over`` of a
sweep and the Python API (``scenes.make_parameters``, ``params.from_mapping``,
``params.set_parameter``).
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass, field
from typing import ClassVar

import pytest

from dolfinx_seal import params, scenes
from dolfinx_seal.cli import main
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import check_positive, from_mapping, refuse_renamed, set_parameter

NUMPY_SCENES = ("flat", "rubber-friction")


# ------------------------------------------------------------ the mechanism
@dataclass(frozen=True)
class Group:
    """A table.

    Attributes:
        speed: A speed [m/s].
        model: A model.
    """

    speed: float = 1.0
    model: str = "a"

    def __post_init__(self) -> None:
        check_positive("group.speed", self.speed, "m/s")


@dataclass(frozen=True)
class Toy:
    """A toy scene.

    Attributes:
        group: The table.
        contact: A table that was a plain parameter.
        size: A size [m].
    """

    RENAMED: ClassVar[dict[str, str | tuple[str, str]]] = {
        "velocity": ("group.speed", "m/s"),
        "old": "group",
        "old.kind": "group.model",
        "contact": ("contact.model", "a or b"),
    }

    group: Group = field(default_factory=Group)
    contact: Group = field(default_factory=Group)
    size: float = 1.0


@dataclass(frozen=True)
class Outer:
    """Toy nested one level down.

    Attributes:
        toy: The toy.
    """

    toy: Toy = field(default_factory=Toy)


def _refused(old: str, new: str, unit: str = "") -> str:
    note = f" [{unit}]" if unit else ""
    return "^" + re.escape(f"'{old}' was renamed: use '{new}'{note}") + "$"


def test_plain_group_and_longest_renames():
    with pytest.raises(ParameterError, match=_refused("velocity", "group.speed", "m/s")):
        from_mapping(Toy, {"size": 2.0, "velocity": 3.0})
    # an old table renames what is under it; a longer old name wins
    with pytest.raises(ParameterError, match=_refused("old.speed", "group.speed")):
        from_mapping(Toy, {"old": {"speed": 3.0}})
    with pytest.raises(ParameterError, match=_refused("old.kind", "group.model")):
        from_mapping(Toy, {"old": {"kind": "b"}})
    with pytest.raises(ParameterError, match=_refused("old.kind", "group.model")):
        refuse_renamed(Toy, {"old.kind": "b"})  # dotted keys as well as nested ones


def test_a_plain_parameter_that_became_a_table():
    with pytest.raises(ParameterError, match=_refused("contact", "contact.model", "a or b")):
        from_mapping(Toy, {"contact": "b"})
    # the table itself (also empty) and its fields are the new parameters
    assert from_mapping(Toy, {"contact": {"model": "b"}}).contact.model == "b"
    assert from_mapping(Toy, {"contact": {}}) == Toy()
    refuse_renamed(Toy, {"contact.model": "b", "group": {"speed": 2.0}, "size": 3.0})


def test_new_names_and_unknown_names_are_not_renames():
    assert from_mapping(Toy, {"group": {"speed": 2.0}}).group.speed == 2.0
    with pytest.raises(ParameterError, match="unknown parameter 'bogus'"):
        from_mapping(Toy, {"bogus": 1.0})
    with pytest.raises(ParameterError, match=r"unknown parameter 'group\.velocity'"):
        from_mapping(Toy, {"group": {"velocity": 1.0}})  # renames are relative to their class


def test_nested_renames_name_the_full_path():
    with pytest.raises(ParameterError, match=_refused("toy.velocity", "toy.group.speed", "m/s")):
        from_mapping(Outer, {"toy": {"velocity": 3.0}})


def test_set_parameter_refuses_an_old_name():
    with pytest.raises(ParameterError, match=_refused("velocity", "group.speed", "m/s")):
        set_parameter(Toy(), "velocity", 2.0)
    with pytest.raises(ParameterError, match=_refused("old.kind", "group.model")):
        set_parameter(Toy(), "old.kind", "b")
    assert set_parameter(Toy(), "group.speed", 2.0).group.speed == 2.0


# ------------------------------------------------------ the numpy scenes
def _cases() -> list[tuple[str, str, str, str]]:
    """(scene, old name as given, new name, unit) for every old name of the numpy scenes;
    an old table is given as one of its fields."""
    out = []
    for scene in NUMPY_SCENES:
        cls = scenes.get(scene).parameters
        for old, entry in cls.RENAMED.items():
            new, unit = (entry, "") if isinstance(entry, str) else entry
            table = params.get_dotted(cls(), new)
            if dataclasses.is_dataclass(table):
                leaf = dataclasses.fields(table)[-1].name
                old, new = f"{old}.{leaf}", f"{new}.{leaf}"
            out.append((scene, old, new, unit))
    return out


CASES = _cases()
IDS = [f"{c[0]}:{c[1]}" for c in CASES]


def test_every_old_name_points_to_a_parameter():
    """The new names exist (and are not tables); no old name is still a parameter."""
    assert len(CASES) >= 20
    for scene, old, new, _ in CASES:
        defaults = scenes.make_parameters(scene)
        value = params.get_dotted(defaults, new)
        assert value is not None and not dataclasses.is_dataclass(value), (scene, new)
        old_value = params.get_dotted(defaults, old)
        assert old_value is None or dataclasses.is_dataclass(old_value), (scene, old)


@pytest.mark.parametrize(("scene", "old", "new", "unit"), CASES, ids=IDS)
def test_old_names_are_refused_in_python(scene, old, new, unit):
    regex = _refused(old, new, unit)
    with pytest.raises(ParameterError, match=regex):
        scenes.make_parameters(scene, overrides=[f"{old}=1"])
    nested: object = "1"
    for part in reversed(old.split(".")):
        nested = {part: nested}
    with pytest.raises(ParameterError, match=regex):
        scenes.make_parameters(scene, values=nested)
    with pytest.raises(ParameterError, match=regex):
        params.from_mapping(scenes.get(scene).parameters, nested)
    with pytest.raises(ParameterError, match=regex):
        scenes.set_parameter(scenes.make_parameters(scene), old, 1.0)


@pytest.mark.parametrize(("scene", "old", "new", "unit"), CASES, ids=IDS)
def test_old_names_are_refused_in_toml(scene, old, new, unit, mpi_tmp_path):
    regex = _refused(old, new, unit)
    path = mpi_tmp_path / f"{scene}-{old}.toml"
    if COMM_WORLD.rank == 0:
        path.write_text(f'scene = "{scene}"\n\n[parameters]\n{old} = "1"\n')  # TOML dotted key
    COMM_WORLD.barrier()
    with pytest.raises(ParameterError, match=regex):
        scenes.make_parameters(scene, path)


@pytest.mark.parametrize(
    ("scene", "old", "new"),
    [("flat", "velocity", "film.speed"), ("flat", "youngs_modulus", "material.E"),
     ("rubber-friction", "velocity", "speed"), ("rubber-friction", "modulus.kind", "material.model"),
     ("rubber-friction", "zeta_max", "roughness.q1")],
)  # fmt: skip
def test_old_names_are_refused_on_the_command_line(scene, old, new, mpi_tmp_path, capsys):
    out = str(mpi_tmp_path / "unused")
    message = f"'{old}' was renamed: use '{new}'"
    assert main(["run", scene, "--set", f"{old}=1", "--out", out]) == 2
    assert main(["params", scene, "--set", f"{old}=1"]) == 2
    assert main(["sweep", scene, "--over", old, "--values", "1,2", "--out", out]) == 2
    err = capsys.readouterr().err
    assert err.count(message) == 3, err
    assert not (mpi_tmp_path / "unused").exists()
