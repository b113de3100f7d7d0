"""The sweep's progress on the terminal: cases done, running, failed and the time left (one
line rewritten on a terminal; one line per finished case otherwise)."""

from __future__ import annotations

import sys
import time
from typing import TextIO


def _clock(seconds: float) -> str:
    s = int(round(max(seconds, 0.0)))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60:02d}:{s % 60:02d}"


class SweepProgress:
    def __init__(self, total: int, slots: int = 1, stream: TextIO | None = None, quiet: bool = False):
        self.total, self.slots = total, max(1, slots)
        self.done = self.failed = 0
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.t0 = time.perf_counter()

    def set_slots(self, slots: int) -> None:
        self.slots = max(1, slots)

    def line(self) -> str:
        elapsed = time.perf_counter() - self.t0
        left = self.total - self.done
        running = min(self.slots, left)
        text = f"{self.done}/{self.total} done, {running} running, {self.failed} failed, {_clock(elapsed)} elapsed"
        if self.done and left:
            text += f", ~{_clock(elapsed / self.done * left)} left"
        return text

    def case_done(self, index: int, status: str, wall_s: float | None, message: str = "") -> None:
        self.done += 1
        if status not in ("ok",):
            self.failed += 1
        if self.quiet:
            return
        if self.tty:
            note = f"  case {index}: {status}" + (f" ({message[:60]})" if message and status != "ok" else "")
            self.stream.write("\r\033[K" + f"sweep: {self.line()}" + (note if status != "ok" else ""))
            if status != "ok":
                self.stream.write("\n")
        else:
            wall = f" {wall_s:.1f} s" if isinstance(wall_s, (int, float)) else ""
            extra = f": {message}" if message and status != "ok" else ""
            self.stream.write(f"sweep: case {index} {status}{wall}{extra} [{self.line()}]\n")
        self.stream.flush()

    def close(self) -> None:
        if self.tty and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()
