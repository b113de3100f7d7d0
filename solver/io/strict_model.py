"""The pydantic base every table of a scene file is validated with: unknown keys are errors that
list the known ones, no NaN or infinity anywhere, values frozen; and the validators that keep
TOML's types apart (``true`` is not 1.0, ``"0.04"`` is not 0.04, 2.5 is not a whole number)."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, model_validator
from pydantic_core import PydanticCustomError

__all__ = ["StrictTable", "number", "integer"]


class StrictTable(BaseModel):
    """Unknown keys are errors that list the known ones; no NaN or infinity anywhere."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        if isinstance(data, dict):
            known = list(cls.model_fields)
            for key in data:
                if key not in cls.model_fields:
                    raise PydanticCustomError(
                        "unknown_key",
                        "unknown key (known: {known})",
                        {"key": str(key), "value": data[key], "known": ", ".join(known)},
                    )
        return data


def number(v: Any) -> Any:
    """A number, not a boolean or a string."""
    if isinstance(v, (bool, str)):
        raise PydanticCustomError("number", "must be a number")
    return v


def integer(v: Any) -> Any:
    """A whole number (an integral float counts), not a boolean or a string."""
    if isinstance(v, (bool, str)) or (isinstance(v, float) and not v.is_integer()):
        raise PydanticCustomError("integer", "must be a whole number")
    return v
