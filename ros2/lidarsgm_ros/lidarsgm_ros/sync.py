"""Time synchronisation of several message streams (as message_filters' exact and approximate policies do; that
package is not among the ROS 2 Python wheels). Pure Python: add(index, stamp_ns, msg) returns the sets it completes.
"""
from collections import deque


class ExactSync:
    """Emits a set when every stream has a message with the same stamp; keeps the queue_size newest stamps."""

    def __init__(self, streams, queue_size=10):
        self.n, self.queue_size = streams, max(int(queue_size), 1)
        self.pending = {}  # stamp -> [msg or None] * n
        self.dropped = 0   # incomplete sets given up
        self.unit = "incomplete sets"

    def add(self, index, stamp, msg):
        slot = self.pending.setdefault(stamp, [None] * self.n)
        slot[index] = msg
        out = []
        if all(m is not None for m in slot):
            del self.pending[stamp]
            for old in [s for s in self.pending if s < stamp]:  # an older set can no longer complete in order
                del self.pending[old]
                self.dropped += 1
            out.append((stamp, slot))
        while len(self.pending) > self.queue_size:
            del self.pending[min(self.pending)]
            self.dropped += 1
        return out

    def held(self):
        """The messages waiting for a set."""
        return [m for slot in self.pending.values() for m in slot if m is not None]

    def finish(self):
        """At the end of the input: the sets still incomplete count as dropped (none can complete)."""
        self.dropped += len(self.pending)
        self.pending.clear()
        return []


class ApproximateSync:
    """Emits a set of one message per stream whose stamps lie within max_interval_ns of each other.

    Per stream the messages arrive in stamp order. The pivot is the latest of the streams' oldest stamps (no set
    can be older); each stream contributes its message nearest to the pivot. The choice is final once every stream
    has a message at or after the pivot, since later messages lie further from it. A set spread wider than
    max_interval_ns is not emitted: the pivot's message is dropped and the search goes on.
    """

    def __init__(self, streams, queue_size=10, max_interval_ns=50000000):
        self.n, self.queue_size, self.max_interval = streams, max(int(queue_size), 1), int(max_interval_ns)
        self.queues = [deque() for _ in range(streams)]
        self.last = [None] * streams  # the newest stamp seen per stream
        self.dropped = 0  # messages given up
        self.unit = "unmatched messages"

    def add(self, index, stamp, msg):
        q = self.queues[index]
        if self.last[index] is not None and stamp <= self.last[index]:
            self.dropped += 1  # out of order: the stream went back in time
            return []
        self.last[index] = stamp
        q.append((stamp, msg))
        if len(q) > self.queue_size:
            q.popleft()
            self.dropped += 1
        return self._match(final=False)

    def _match(self, final):
        out = []
        while all(self.queues):
            pivot_stream = max(range(self.n), key=lambda i: self.queues[i][0][0])
            pivot = self.queues[pivot_stream][0][0]
            if not final and any(qq[-1][0] < pivot for qq in self.queues):
                break  # a stream may still send a message nearer the pivot
            picks = []
            for qq in self.queues:
                best = min(range(len(qq)), key=lambda k: abs(qq[k][0] - pivot))
                picks.append(best)
            stamps = [qq[k][0] for qq, k in zip(self.queues, picks)]
            if max(stamps) - min(stamps) > self.max_interval:
                self.queues[pivot_stream].popleft()
                self.dropped += 1
                continue
            out.append((pivot, [qq[k][1] for qq, k in zip(self.queues, picks)]))
            for qq, k in zip(self.queues, picks):
                for _ in range(k + 1):
                    qq.popleft()
                self.dropped += k
        return out

    def held(self):
        """The messages waiting for a set."""
        return [m for q in self.queues for _, m in q]

    def finish(self):
        """At the end of the input (no message will follow): the sets still to be had, and the messages left over
        count as dropped."""
        out = self._match(final=True)
        self.dropped += sum(len(q) for q in self.queues)
        for q in self.queues:
            q.clear()
        return out
