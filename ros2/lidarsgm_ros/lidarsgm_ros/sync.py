"""Time synchronisation of several message streams (as message_filters' exact and approximate policies do; that
package is not among the ROS 2 Python wheels). Pure Python: add(index, stamp_ns, msg) returns the sets it completes.

LidarPairing puts the two together as the node and the bag command use them: the four image streams synchronised
(ExactSync or ApproximateSync), and each image set then paired with its cloud, or let go without one when the LiDAR
is silent, so that a LiDAR drop-out never stops the depth.
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

    def reset(self):
        """Forgets what waits (a jump in time: it can no longer complete); counted as dropped."""
        self.finish()

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

    def reset(self):
        """Forgets what waits and the streams' newest stamps (a jump in time); what waited counts as dropped."""
        self.dropped += sum(len(q) for q in self.queues)
        for q in self.queues:
            q.clear()
        self.last = [None] * self.n

    def finish(self):
        """At the end of the input (no message will follow): the sets still to be had, and the messages left over
        count as dropped."""
        out = self._match(final=True)
        self.dropped += sum(len(q) for q in self.queues)
        for q in self.queues:
            q.clear()
        return out


class LidarPairing:
    """Pairs each complete image set with the LiDAR cloud of its stamp, or lets it go without one.

    Streams 0-3 are the images' (left image and camera_info, right image and camera_info), synchronised by `images`
    (an ExactSync or ApproximateSync of four streams); stream 4 is the cloud's. A complete image set waits for the
    cloud of its stamp (the same stamp, or with tolerance_ns > 0 the nearest within it, final once a cloud at or
    after the set's stamp has arrived). It goes without one (stereo alone) once none can pair with it any more:
    a cloud beyond it arrived; an image set lidar_timeout_ns newer completed, or lidar_timeout_ns passed on the
    caller's clock since the set completed (poll(now_ns); the node passes its clock, the bag command none); or the
    input ended (finish()). After such a timeout the LiDAR counts as silent until its next cloud: an image set then
    waits only until the next image set completes, so a drop-out costs one frame of latency, not lidar_timeout.
    Every stream arrives in stamp order; a stamp that repeats or goes back on any stream (a bag played in a loop,
    a clock reset) starts over: what waits goes out with what it has, and the synchronisers forget the rest.

    add(), poll() and finish() return the sets that go out, in stamp order: (stamp, [left, left_info, right,
    right_info, cloud or None]).
    """

    CLOUD = 4

    def __init__(self, images, tolerance_ns=0, lidar_timeout_ns=500000000, queue_size=10):
        self.images, self.tolerance, self.timeout = images, int(tolerance_ns), int(lidar_timeout_ns)
        self.queue_size = max(int(queue_size), 1)
        self.waiting = deque()  # [stamp, image messages, the caller's clock when complete] in stamp order
        self.clouds = deque()   # (stamp, cloud) not yet paired, in stamp order
        self.last = [None] * 5  # the newest stamp per stream
        self.silent = False     # the LiDAR missed a set by timeout and sent nothing since
        self.restarts = 0       # jumps back in time
        self.unpaired_clouds = 0
        self.dropped, self.unit = 0, "messages"

    # -- input
    def add(self, index, stamp, msg, now=None):
        out = []
        if self.last[index] is not None and stamp <= self.last[index]:
            out += self._restart()
        self.last[index] = stamp
        if index == self.CLOUD:
            self.silent = False
            self.clouds.append((stamp, msg))
            while len(self.clouds) > self.queue_size:
                self.clouds.popleft()
                self.unpaired_clouds += 1
        else:
            for s, msgs in self.images.add(index, stamp, msg):
                self.waiting.append([s, msgs, now])
        self.dropped = self.images.dropped + self.unpaired_clouds
        return out + self._release(now)

    def poll(self, now):
        """The sets whose wait for a cloud has lasted lidar_timeout_ns on the caller's clock."""
        return self._release(now)

    def finish(self):
        """At the end of the input: every waiting set goes, with the cloud it can have."""
        for s, msgs in self.images.finish():
            self.waiting.append([s, msgs, None])
        out = self._release(None, final=True)
        self.unpaired_clouds += len(self.clouds)
        self.clouds.clear()
        self.dropped = self.images.dropped + self.unpaired_clouds
        return out

    def held(self):
        """The messages waiting (for a set, or a set for its cloud)."""
        return self.images.held() + [m for _, msgs, _ in self.waiting for m in msgs] + [c for _, c in self.clouds]

    def _restart(self):
        out = self._release(None, final=True)
        self.restarts += 1
        self.images.reset()
        self.unpaired_clouds += len(self.clouds)
        self.clouds.clear()
        self.last = [None] * 5
        return out

    # -- pairing
    def _candidate(self, stamp):
        """The cloud nearest to stamp within the tolerance (its index in self.clouds), or None."""
        best = None
        for k, (cs, _) in enumerate(self.clouds):
            if abs(cs - stamp) <= self.tolerance and (best is None or abs(cs - stamp) < abs(self.clouds[best][0] - stamp)):
                best = k
        return best

    def _release(self, now, final=False):
        out = []
        while self.waiting:
            stamp, msgs, since = self.waiting[0]
            k = self._candidate(stamp)
            newest_cloud = self.clouds[-1][0] if self.clouds else self.last[self.CLOUD]
            beyond = newest_cloud is not None and newest_cloud >= stamp  # no later cloud lies nearer
            if k is not None and (beyond or self.tolerance == 0):
                out.append(self._go(k))
                continue
            passed = newest_cloud is not None and newest_cloud > stamp + self.tolerance
            newer = self.waiting[-1][0] if len(self.waiting) > 1 else None
            timed_out = (newer is not None and newer - stamp >= self.timeout) or \
                (now is not None and since is not None and now - since >= self.timeout)
            if not (final or passed or timed_out or (self.silent and newer is not None)):
                break  # its cloud may still come
            if timed_out and k is None:
                self.silent = True
            out.append(self._go(k))
        return out

    def _go(self, k):
        stamp, msgs, _ = self.waiting.popleft()
        cloud = None
        if k is not None:
            for _ in range(k):  # older clouds than the one taken cannot pair with a later set
                self.clouds.popleft()
                self.unpaired_clouds += 1
            cloud = self.clouds.popleft()[1]
        while self.clouds and self.clouds[0][0] < stamp - self.tolerance:
            self.clouds.popleft()
            self.unpaired_clouds += 1
        return stamp, list(msgs) + [cloud]
