"""What a live measured-mode identification keeps: a rolling, bounded store of stamped rows.

A real rig may stream for hours; the identification node keeps at most ``capacity`` rows per
stream (load samples, marker poses) in preallocated numpy arrays that grow by doubling up to
the bound, so memory is bounded before any work: ``capacity`` x (8 + 8 x width) bytes. Past the
bound the OLDEST messages are dropped, whole (a message's rows are never split), and counted:
the identification then sees the most recent stretch of the record, and says how much it left
out (issue 23, point 3).
"""
import numpy as np

__all__ = ["KeptRows"]

FIRST_ROWS = 4096


class KeptRows:
    """At most ``capacity`` rows of ``width`` floats, each with an int64 stamp [ns] and the
    number of the message it came in; the oldest messages go first when full."""

    def __init__(self, capacity, width):
        self.capacity = int(capacity)
        self.width = int(width)
        size = min(self.capacity, FIRST_ROWS)
        self.stamps = np.zeros(size, np.int64)
        self.values = np.zeros((size, width))
        self.message = np.zeros(size, np.int64)
        self.start = 0      # index of the oldest row
        self.size = 0       # rows kept
        self.count = 0      # messages pushed (numbers the messages)
        self.dropped_messages = 0
        self.dropped_rows = 0

    def _grow(self, needed):
        if len(self.stamps) >= min(needed, self.capacity):
            return
        new = min(self.capacity, max(needed, 2 * len(self.stamps)))
        order = self._order()
        self.stamps = np.concatenate([self.stamps[order], np.zeros(new - self.size, np.int64)])
        self.values = np.concatenate([self.values[order], np.zeros((new - self.size,
                                                                    self.width))])
        self.message = np.concatenate([self.message[order],
                                       np.zeros(new - self.size, np.int64)])
        self.start = 0

    def _order(self):
        return (self.start + np.arange(self.size)) % len(self.stamps)

    def _drop_oldest(self, rows):
        """Drop the oldest messages until ``rows`` rows are free."""
        length = len(self.stamps)
        while self.size and self.size + rows > length:
            first, n = self.message[self.start], 1
            while n < self.size and self.message[(self.start + n) % length] == first:
                n += 1
            self.start = (self.start + n) % len(self.stamps)
            self.size -= n
            self.dropped_rows += n
            self.dropped_messages += 1

    def push(self, stamp_ns, rows):
        """Keep one message: ``rows`` (k, width) stamped ``stamp_ns``; False (nothing kept)
        if the message alone is larger than the bound."""
        rows = np.asarray(rows, float).reshape(-1, self.width)
        k = len(rows)
        if k > self.capacity:
            return False
        self._grow(self.size + k)
        self._drop_oldest(k)
        at = (self.start + self.size + np.arange(k)) % len(self.stamps)
        self.stamps[at], self.values[at], self.message[at] = stamp_ns, rows, self.count
        self.size += k
        self.count += 1
        return True

    def rows(self):
        """(stamps [ns] (n,), values (n, width), message numbers (n,)), oldest first."""
        order = self._order()
        return self.stamps[order], self.values[order], self.message[order]

    def messages(self):
        """[(stamp [ns], rows (k, width))] per kept message, oldest first."""
        stamps, values, numbers = self.rows()
        if not len(numbers):
            return []
        cuts = np.flatnonzero(np.diff(numbers)) + 1
        return [(int(s[0]), v) for s, v in zip(np.split(stamps, cuts), np.split(values, cuts))]

    def nbytes(self):
        """Bytes of the arrays now allocated."""
        return self.stamps.nbytes + self.values.nbytes + self.message.nbytes
