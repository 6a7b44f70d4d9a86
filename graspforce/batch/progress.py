"""A progress bar on stderr with the rate and the time left; plain text, no dependency."""
import sys
import time


def clock(seconds):
    if seconds != seconds or seconds == float("inf"):
        return "--:--"
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


class Progress:
    """done/total rows; `advance(k)` after each chunk. On a terminal the line is redrawn in
    place; elsewhere (a log file) a line is printed at most every `every` seconds. The rate
    counts this run's rows only, so a resumed run's ETA is not flattered by skipped chunks."""

    def __init__(self, total, done=0, unit="wrenches", stream=None, enabled=True, every=2.0):
        self.total, self.done, self.unit = total, done, unit
        self.stream = sys.stderr if stream is None else stream
        self.enabled = enabled
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.every = 0.1 if self.tty else every
        self.start = time.perf_counter()
        self.first = done
        self.last = -1e9

    def advance(self, k):
        self.done += k
        now = time.perf_counter()
        if self.enabled and (now - self.last >= self.every or self.done >= self.total):
            self.last = now
            self._draw(now)

    def line(self, now=None):
        now = time.perf_counter() if now is None else now
        elapsed = max(now - self.start, 1e-9)
        rate = (self.done - self.first) / elapsed
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        frac = self.done / self.total if self.total else 1.0
        width = 30
        bar = "#" * int(frac * width) + "." * (width - int(frac * width))
        return (f"[{bar}] {100 * frac:5.1f}% {self.done:,}/{self.total:,} {self.unit} "
                f"{rate:,.0f}/s elapsed {clock(elapsed)} ETA {clock(left)}")

    def _draw(self, now):
        end = "" if self.tty and self.done < self.total else "\n"
        self.stream.write(("\r" if self.tty else "") + self.line(now) + end)
        self.stream.flush()
