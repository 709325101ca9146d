"""polyaxis: multi-axis process planning for layered manufacturing, from Python.

The calls mirror the CLI's commands and take the same options by the same names:

    import polyaxis
    plan = polyaxis.plan("part.stl")                     # the default machine and process
    plan = polyaxis.plan("part.stl", polyaxis.PlanOptions(layers="planar", perimeters=3))
    plan.program["tip"]                                  # (n, 3) numpy view, mm
    plan.write("out")                                    # the CLI's files: <part>.ngc, plan.json, report.html, ...

Errors raise polyaxis.Error subclasses whose exit_code is the CLI's exit code for the same failure
(UsageError 2, InvalidInputError 3, InfeasibleError 4, MachineLimitError 5, OutputError 6).
See docs/python.md.
"""

from ._polyaxis import (  # noqa: F401
    AnalyzeOptions, Analysis, Error, InfeasibleError, InternalError, InvalidInputError, LaminateOptions,
    Lamination, MachineLimitError, OutputError, Part, PartOptions, Plan, PlanOptions, SimulateOptions,
    SliceOptions, Slices, UsageError, analyze, inspect, laminate, plan, read_part, simulate, slice)

__all__ = [
    "AnalyzeOptions", "Analysis", "Error", "InfeasibleError", "InternalError", "InvalidInputError",
    "LaminateOptions", "Lamination", "MachineLimitError", "OutputError", "Part", "PartOptions", "Plan",
    "PlanOptions", "SimulateOptions", "SliceOptions", "Slices", "UsageError", "analyze", "inspect",
    "laminate", "plan", "read_part", "simulate", "slice",
]


def _keyword_constructor(cls):
    """Lets CLS take its fields as keywords: PlanOptions(layers="planar", perimeters=3)."""
    plain_init = cls.__init__

    def __init__(self, **fields):
        plain_init(self)
        for name, value in fields.items():
            if name.startswith("_") or not hasattr(self, name):
                raise UsageError(f"{cls.__name__}: unknown option '{name}'")
            setattr(self, name, value)

    __init__.__doc__ = f"{cls.__name__}(**fields): the CLI's defaults, then FIELDS by name."
    cls.__init__ = __init__
    return cls


for _cls in (PartOptions, PlanOptions, SliceOptions, AnalyzeOptions, SimulateOptions, LaminateOptions):
    _keyword_constructor(_cls)
del _cls
