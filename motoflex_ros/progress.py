"""Progress bars that suit a terminal and a log file alike (issue 24, point 9).

On a terminal: tqdm's live bar. Anywhere else (a log, a pipe, CI): tqdm would still redraw its
bar with carriage returns, a hundred updates on one "line" of the log; here it writes a whole
line instead, one per ``step_percent`` of the total (one per ``log_interval_s`` when the total
is unknown), and a last line when the bar closes.
"""
import sys

from tqdm import tqdm

__all__ = ["progress_bar", "LogLines", "is_terminal"]

STEP_PERCENT = 10
LOG_INTERVAL_S = 30.0


def is_terminal(stream):
    """Is ``stream`` an interactive terminal?"""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):   # no isatty, or closed
        return False


class _Discard:
    """Where tqdm's own drawing (carriage returns, the closing newline) goes in a log."""

    def write(self, text):
        return len(text)

    def flush(self):
        pass


class LogLines(tqdm):
    """tqdm that writes a whole line per ``step_percent`` of the total to ``out``."""

    def __init__(self, *args, out=None, step_percent=STEP_PERCENT, **kwargs):
        self._out = sys.stderr if out is None else out
        self._step = step_percent
        self._shown = None
        kwargs.update(file=_Discard(), mininterval=0.0, miniters=1, dynamic_ncols=False,
                      ncols=80)
        super().__init__(*args, **kwargs)

    def _mark(self):
        total = self.total
        if total:
            return int(100.0 * min(self.n, total) / total // self._step)
        return int(self.format_dict["elapsed"] // LOG_INTERVAL_S)

    def display(self, msg=None, pos=None):
        """Write the bar as a line when it crossed a step (always when it closes)."""
        if msg == "":   # tqdm clearing a bar that does not stay: nothing was drawn in place
            return True
        mark = self._mark()
        closing = self.disable   # tqdm.close sets disable before its last display
        if mark == self._shown and not closing:
            return True
        if closing and mark == self._shown and self._shown is not None and self.total \
                and self.n >= self.total:
            return True   # the 100 % line is already there
        self._shown = mark
        self._out.write(self.__str__().rstrip() + "\n")
        self._out.flush()
        return True


def progress_bar(iterable=None, *, total=None, desc=None, unit="it", enabled=True,
                 file=None, **kwargs):
    """A progress bar on ``file`` (default stderr): tqdm on a terminal, :class:`LogLines`
    elsewhere, and a disabled tqdm (same methods, no output) when not ``enabled``."""
    stream = sys.stderr if file is None else file
    if not enabled:
        return tqdm(iterable, total=total, disable=True)
    if is_terminal(stream):
        return tqdm(iterable, total=total, desc=desc, unit=unit, file=stream, **kwargs)
    return LogLines(iterable, total=total, desc=desc, unit=unit, out=stream, **kwargs)
