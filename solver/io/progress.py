"""Progress display for long runs, written to stderr.

The solver calls ``progress(message, fraction=None)`` at its milestones (``fraction`` in
[0, 1] of the whole run when it knows it, e.g. ``progress("load step 3/10", 0.3)``). Extra
keyword arguments are shown as ``key=value``. Nothing is shown during the first ``delay``
seconds, so short runs stay quiet; on a terminal one line is rewritten in place, otherwise
a line is printed at most every ``interval`` seconds (log files stay short).
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO

__all__ = ["ProgressReporter", "silent", "share"]


def silent(*args: Any, **kwargs: Any) -> None:
    """A progress callback that shows nothing."""


def share(progress, low: float, high: float, prefix: str = ""):
    """``progress`` for one part of a run that takes the fractions ``low`` to ``high`` of it: the
    part's own fractions (0 to 1) are mapped there and its messages start with ``prefix``."""
    def report(*args: Any, **kwargs: Any) -> None:
        args = list(args)
        if "fraction" in kwargs and kwargs["fraction"] is not None:
            kwargs["fraction"] = low + (high - low) * float(kwargs["fraction"])
        elif len(args) > 1 and isinstance(args[1], (int, float)) and not isinstance(args[1], bool):
            args[1] = low + (high - low) * float(args[1])
        if args and prefix:
            args[0] = f"{prefix}{args[0]}"
        progress(*args, **kwargs)

    return report


class ProgressReporter:
    def __init__(
        self,
        stream: TextIO | None = None,
        delay: float = 1.0,
        interval: float | None = None,
        clock=time.monotonic,
    ):
        self.stream = stream if stream is not None else sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.delay = delay
        self.interval = interval if interval is not None else (0.1 if self.tty else 5.0)
        self.clock = clock
        self.start = clock()
        self.last_shown: float | None = None
        self.pending: str | None = None
        self.width = 0

    @staticmethod
    def format(*args: Any, **kwargs: Any) -> str:
        fraction = kwargs.pop("fraction", None)
        parts = []
        for a in args:
            if isinstance(a, float) and fraction is None and 0.0 <= a <= 1.0 and parts:
                fraction = a
            elif isinstance(a, dict):
                parts.extend(f"{k}={_short(v)}" for k, v in a.items())
            else:
                parts.append(str(a))
        parts.extend(f"{k}={_short(v)}" for k, v in kwargs.items())
        text = " ".join(parts)
        if fraction is not None:
            text += f" ({100.0 * float(fraction):.0f} %)"
        return text

    def __call__(self, *args: Any, **kwargs: Any) -> None:
        now = self.clock()
        elapsed = now - self.start
        line = f"[{elapsed:7.1f} s] {self.format(*args, **kwargs)}"
        if elapsed < self.delay or (self.last_shown is not None and now - self.last_shown < self.interval):
            self.pending = line
            return
        self._show(line)
        self.last_shown = now
        self.pending = None

    def _show(self, line: str) -> None:
        if self.tty:
            self.stream.write("\r" + line.ljust(self.width))
            self.width = len(line)
        else:
            self.stream.write(line + "\n")
        self.stream.flush()

    def close(self) -> None:
        """End the display: the last message is shown if the run was long enough to show any."""
        if self.pending is not None and self.last_shown is not None:
            self._show(self.pending)
        if self.tty and self.width:
            self.stream.write("\n")
            self.stream.flush()
        self.pending = None
        self.width = 0  # closing twice adds nothing


def _short(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)
