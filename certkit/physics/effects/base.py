"""What an effect of the drop model is made of, as the effect registry holds it.

An effect is defined once, in its own module of :mod:`certkit.physics.effects`, as an
:class:`Effect`: its one name in the spec and its one label everywhere else, the model term
that carries its parameters into the compiled equations of motion, how that term is built
from the campaign spec, the calibration knobs it adds, the one-parameter families (its
forms) the gap diagnosis tests for it (:class:`Candidate`) and the withheld form the blind check simulates
(:class:`Truth`).  The stages that use effects (spec checks, the gear model, calibration,
attribution, the blind check) read them from the registry and nowhere else.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

from certkit.physics.drop_model import DropModel, Orifice


@dataclass(frozen=True)
class Knob:
    """A model parameter calibration may move: how to read and set it, and its bounds."""

    name: str
    label: str
    unit: str
    read: Callable[[DropModel], float]
    write: Callable[[DropModel, float], DropModel]
    bounds: Callable[[float], tuple[float, float]]
    needs: str | None = None   # the label of the effect that must be on for this knob


@dataclass(frozen=True)
class Candidate:
    """One form of an effect as a one-parameter family nesting the nominal model (the gap
    diagnosis).  An effect may have several forms (friction proportional to a constant or
    to the gas force, a loop scaling with the tyre curve or of constant amplitude): the
    diagnosis names the effect, and the form that fitted it best."""

    name: str                                        # the effect's label
    unit_size: str                                   # what strength 1 means, in words
    add: Callable[[DropModel, float], DropModel]     # the model with the effect at strength φ
    probe: float = 0.05                              # φ of the finite-difference signature
    form: str = ""                                   # the form's name ("": the effect's only one)
    #: the recorded channel this form changes sample by sample, without memory (a sensor's
    #: gain): its correction must fit that channel's residual at the same instant, which
    #: the diagnosis checks (:func:`certkit.gap.residuals.shifted_fit`); "" for the others
    memoryless_on: str = ""
    #: why the form cannot be added to a calibrated model, in words ("" when it can): a form
    #: whose family is empty at that model is skipped with this reason, never built
    inapplicable: Callable[[DropModel], str] | None = None
    #: the quantities ``unit_size`` states in SI, (its words for one, value [SI], SI unit):
    #: a report shows them in the campaign's display units
    quantities: tuple = ()
    #: parameters of the form fitted with its strength when it is refitted, as (Knob, the
    #: values its profile tries: the first is the refit's default start) pairs, written after
    #: the form is added (a load channel's skew beside its gain)
    knobs: tuple = ()

    def why_not(self, model: DropModel) -> str:
        """"" when the form can be added to ``model``, else why not, in words."""
        return self.inapplicable(model) if self.inapplicable else ""

    @property
    def key(self) -> str:
        """The form's one name among all candidates: "effect (form)", or the effect's label
        when it has one form."""
        return f"{self.name} ({self.form})" if self.form else self.name


@dataclass(frozen=True)
class Truth:
    """An effect as the blind check's truth generator has it, at a size s > 0."""

    candidate: str        # the library candidate a right diagnosis names
    form: str             # the truth's form, and how it differs from the candidate
    sizes: tuple          # (smallest, largest) s searched when sizing
    mechanics: Callable[[DropModel, float], DropModel] | None = None
    sensor: Callable | None = None     # s -> a recorder of the channels (sensor dynamics)
    #: what the truth's size is measured from, when that is not the nominal model itself
    base: Callable[[DropModel], DropModel] | None = None

    def model(self, model: DropModel, size: float) -> DropModel:
        return self.mechanics(model, size) if self.mechanics else model

    def start(self, model: DropModel) -> DropModel:
        return self.base(model) if self.base else model

    def recorder(self, size: float):
        return self.sensor(size) if self.sensor else None


@dataclass(frozen=True)
class Gear:
    """What an effect's builder reads of one gear unit: its spec, the campaign's platform
    and the nominal strut it adds to (all SI), and where to point a user at a bad value."""

    unit: object              # the spec's GearUnit
    index: int                # its position in gear_units
    platform: object | None   # instrumentation.platform of the spec
    orifice: Orifice          # the nominal orifice
    unsprung_mass: float      # m2 [kg]
    spec_file: str
    line: Callable[[tuple], int | None]   # spec location -> line (None when unknown)


@dataclass(frozen=True)
class Effect:
    """One effect of the library, defined once."""

    label: str                           # its one label (reports, records, the diagnosis)
    name: str | None = None              # its one name in a spec's model.effects
    needs: tuple = ()                    # spec locations it reads, from the gear unit
    build: Callable[[Gear], object] | None = None    # the model term, from the spec
    knobs: tuple = ()                    # calibration knobs it adds
    candidates: tuple = ()               # its families (forms) in the gap diagnosis
    truth: Truth | None = None           # its withheld form in the blind check


def set_effect(model: DropModel, label: str, **values) -> DropModel:
    """``model`` with some parameters of its effect ``label`` replaced (SI values)."""
    effects = tuple(replace(e, **values) if e.name == label else e for e in model.effects)
    return replace(model, effects=effects)
