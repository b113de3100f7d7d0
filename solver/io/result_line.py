"""The lines ``ibfem run`` prints per contact: the contact's size and forces in the units of the
summary, only the quantities its type has, and for a symmetric model the force of the whole
contact beside the model's own ("quarter model: 3.42e+06 N; full contact 1.37e+07 N")."""

from __future__ import annotations

from typing import Any, Mapping

__all__ = ["PARTS", "contact_line", "share_name", "accuracy_line"]

_SHARES = {1.0: "full", 0.5: "half", 0.25: "quarter", 0.125: "eighth"}


def share_name(share: float) -> str:
    """'half model', 'quarter model', ... or 'model holding 0.3 of the contact'."""
    for value, name in _SHARES.items():
        if abs(share - value) <= 1e-6 * value:
            return f"{name} model"
    return f"model holding {share:.3g} of the contact"


def _number(value: Any, unit: str) -> str:
    return f"{float(value):.6g} {unit}" if isinstance(value, (int, float)) and value == value else "n/a"


def _vector(value: Any, unit: str) -> str:
    items = value if isinstance(value, (list, tuple)) else []
    return "[" + ", ".join(f"{float(x):.6g}" if x is not None else "n/a" for x in items) + f"] {unit}"


def _size(c: Mapping[str, Any], force_unit: str) -> str | None:
    if "semi_axes" in c:
        return f"semi_axes = {_vector(c.get('semi_axes'), 'm')}"
    return f"half_width = {_number(c.get('half_width'), 'm')}"


def _stick_size(c: Mapping[str, Any], force_unit: str) -> str | None:
    if "stick_semi_axes" in c:
        return f"stick_semi_axes = {_vector(c.get('stick_semi_axes'), 'm')}"
    if "stick_half_width" in c:
        return f"stick_half_width = {_number(c.get('stick_half_width'), 'm')}"
    return None


def _normal_force(c: Mapping[str, Any], force_unit: str) -> str | None:
    full = c.get("full_contact")
    if full:
        return (f"normal_force ({share_name(full['model_share'])}) = {_number(c.get('normal_force'), force_unit)}; "
                f"full contact {_number(full.get('normal_force'), force_unit)}")
    return f"normal_force = {_number(c.get('normal_force'), force_unit)}"


def _tangential_force(c: Mapping[str, Any], force_unit: str) -> str | None:
    if "tangential_force" not in c:
        return None
    q = c.get("tangential_force")
    return "tangential_force = " + (_vector(q, force_unit) if isinstance(q, list) else _number(q, force_unit))


def _percent(value: Any) -> str:
    items = value if isinstance(value, (list, tuple)) else [value]
    return "/".join(f"{100 * float(v):.2g} %" if isinstance(v, (int, float)) and v == v else "n/a" for v in items)


def _estimated_error(c: Mapping[str, Any], force_unit: str) -> str | None:
    errors = c.get("estimated_error")
    if not isinstance(errors, Mapping) or not errors:  # none: a contact that carries no force
        return None
    return "estimated error " + ", ".join(f"{key} {_percent(value)}" for key, value in errors.items())


#: the parts of the line, in order: each takes the contact block (without the keys its type does
#: not have) and the force unit (N in 3D, N/m in 2D) and gives its text, or None to leave it
#: out. A further quantity is shown by appending a part.
PARTS = [_size, _stick_size, _normal_force, _tangential_force, _estimated_error]


def contact_line(c: Mapping[str, Any]) -> str:
    """One contact block of the summary (JSON-safe) as a line of text (:data:`PARTS`): the
    stick region only for a frictional contact, the tangential force not for a frictionless one."""
    kind = c.get("type")
    c = {k: v for k, v in c.items()
         if not (k.startswith("stick_") and kind in ("tied", "frictionless"))
         and not (k == "tangential_force" and kind == "frictionless")}
    force_unit = "N" if "semi_axes" in c else "N/m"
    return ", ".join(text for part in PARTS if (text := part(c, force_unit)) is not None)


def accuracy_line(ladder: Mapping[str, Any]) -> str:
    """The ladder a run with an accuracy target ran: each rung's dofs and largest estimated error."""
    rungs = ladder.get("rungs") or []
    steps = "; ".join(f"{r.get('dofs')} dofs, {_percent(r.get('largest_error'))}"
                      + (f" ({r['quantity']})" if r.get("quantity") else "") for r in rungs)
    verdict = "reached" if ladder.get("reached") else "not reached"
    return f"accuracy {100 * float(ladder.get('target', float('nan'))):g} % {verdict} in {len(rungs)} rung(s): {steps}"
