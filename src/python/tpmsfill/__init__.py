"""tpmsfill: TPMS lattices clipped to any triangle mesh, proved closed and manifold.

The library's functions over numpy arrays; lengths are millimetres. Errors are raised as
tpmsfill.Error and its subclasses (InputError, ParseError, IoError, ResourceError,
ValidationError, Cancelled), each with the library's one-sentence message. The long functions
take progress=callable(stage, fraction), whose False cancels; Ctrl-C cancels them too.
"""
from ._tpmsfill import (  # noqa: F401
    Cancelled,
    Error,
    InputError,
    IoError,
    ParseError,
    ResourceError,
    ValidationError,
    check,
    conformal,
    decimate,
    field_fit,
    fill,
    repair,
    slice,
)

__all__ = ["check", "repair", "fill", "slice", "decimate", "field_fit", "conformal", "Error", "InputError", "ParseError", "IoError", "ResourceError",
           "ValidationError", "Cancelled"]
