"""stickslip: friction laws under event-free numerical integration (Yoo & Lee 2008).

The Fortran core integrates; this package validates input, calls it once per simulation
and returns numpy arrays. The documentation (docs/, built by scripts/docs) explains the laws,
scenes and integrators.
"""
from .core import (
    CONTROL_DEFAULTS,
    CONTROLS,
    DEFAULTS,
    EVENT_DTYPE,
    ContactSolverFailure,
    DivergedSolution,
    EventAccumulation,
    EventBudgetExhausted,
    REGISTRY,
    LAW_PARAMS,
    LAWS,
    METHODS,
    SCENES,
    IntegrationError,
    NewtonFailure,
    NonFiniteSolution,
    OutputBufferFull,
    Result,
    UnstableStepWarning,
    UnusedParameterWarning,
    StepBudgetExhausted,
    StepSizeTooSmall,
    StiffnessDetected,
    friction_coefficient,
    simulate,
    status_message,
)
from .batch import BatchResult
from .sweep import simulate_batch
from .advise import Advice, advise
from .prescribed import PrescribedResult, law_n_states, law_state_labels, prescribed_motion
from .data import Record, damper_files, load_damper_record
from .identify import FitResult, Selection, fit_friction, select_friction_law
from .experiments import (SteadyCurve, SteadyPoints, TwoStepFit, fit_stribeck_curve, fit_two_step,
                          steady_friction)
from .engines import ENGINES, advise_engine, engine_creep, engine_mu
from . import signal
from .model import Model, ModelWarning
from .energy import ConsistencyWarning, EnergyBoundWarning
from .core import RegularisedLawWarning
from .steady import (Branch, Equilibrium, GuessShapeError, LawStatesUnsupported, MonodromyWarning, NoConvergence,
                     NonPeriodicForcing, Orbit, SteadyStateError, continuation, equilibrium, frequency_response,
                     periodic_orbit)

__all__ = [
    "CONTROL_DEFAULTS", "CONTROLS", "REGISTRY", "DEFAULTS", "LAW_PARAMS", "LAWS", "METHODS", "SCENES", "IntegrationError", "NewtonFailure",
    "NonFiniteSolution", "OutputBufferFull", "Result", "StepBudgetExhausted",
    "StepSizeTooSmall", "StiffnessDetected", "friction_coefficient", "simulate",
    "status_message", "BatchResult", "simulate_batch", "UnusedParameterWarning",
    "UnstableStepWarning", "Advice", "advise",
    "EVENT_DTYPE", "ContactSolverFailure", "EventAccumulation", "EventBudgetExhausted",
    "DivergedSolution",
    "PrescribedResult", "law_n_states", "law_state_labels", "prescribed_motion",
    "Record", "damper_files", "load_damper_record", "FitResult", "fit_friction", "Selection", "select_friction_law",
    "SteadyPoints", "SteadyCurve", "TwoStepFit", "steady_friction", "fit_stribeck_curve", "fit_two_step",
    "ENGINES", "advise_engine", "engine_creep", "engine_mu",
    "Model", "ModelWarning", "signal", "EnergyBoundWarning", "ConsistencyWarning", "RegularisedLawWarning",
    "Orbit", "Branch", "Equilibrium", "SteadyStateError", "NoConvergence", "NonPeriodicForcing", "GuessShapeError",
    "LawStatesUnsupported", "MonodromyWarning", "periodic_orbit", "equilibrium", "continuation", "frequency_response",
]
__version__ = "0.1.0"
