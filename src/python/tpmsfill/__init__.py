"""tpmsfill: TPMS lattices clipped to any triangle mesh, proved closed and manifold.

The library's functions over numpy arrays; lengths are millimetres. Errors are raised as
tpmsfill.Error and its subclasses (InputError, ParseError, IoError, ResourceError,
ValidationError, Cancelled), each with the library's one-sentence message.
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
    fill,
)

__all__ = ["check", "fill", "Error", "InputError", "ParseError", "IoError", "ResourceError",
           "ValidationError", "Cancelled"]
