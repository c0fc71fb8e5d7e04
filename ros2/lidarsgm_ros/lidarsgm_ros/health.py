"""What the node and the bag command tell about each set and about themselves (diagnostic_msgs).

Each set that goes out has a status on fusion_status (a DiagnosticArray with the images' header, one status): OK
"fused with the LiDAR", or WARN "stereo alone (<class>): <reason>", the class one of fusion.ALONE_CLASSES. The
node also publishes /diagnostics once a second: one status, "lidarsgm: fusion", whose values count what happened
and whose level follows these rules, over the last report_seconds:
- ERROR: messages arrived but no set went out for dark_seconds (the depth is dark: every set skipped, or no set
  complete);
- WARN: a set went as stereo alone, a set or message was skipped (bad message, overload), the synchroniser
  restarted (time went back), the newest matching residual is above 1 px, or no message arrived at all;
- OK: otherwise (every set fused with the LiDAR).
The message names every rule that applies, the worst first, with its newest cause.
"""
import statistics
import threading
from collections import Counter, deque

from .fusion import ALONE_CLASSES

OK, WARN, ERROR = 0, 1, 2
LEVEL_NAMES = ("OK", "WARN", "ERROR")
FUSION_STATUS = "fusion_status"
NAME = "lidarsgm: fusion"


def set_status(result):
    """(level, message) of one set that went out."""
    if not result.stereo_alone:
        return OK, "fused with the LiDAR"
    return WARN, "stereo alone (%s): %s" % (result.stereo_alone, result.reason)


def diagnostic_array(new, header, level, message, values, level_of=int):
    """A diagnostic_msgs/DiagnosticArray of one status. new(type_name, **fields) makes a message (a MessageKit's
    constructor); level_of turns 0/1/2 into the library's byte (bytes for rclpy, int for rosbags)."""
    status = new("diagnostic_msgs/msg/DiagnosticStatus", level=level_of(level), name=NAME, message=message,
                 hardware_id="lidarsgm",
                 values=[new("diagnostic_msgs/msg/KeyValue", key=k, value=str(v)) for k, v in values])
    return new("diagnostic_msgs/msg/DiagnosticArray", header=header, status=[status])


def _ms(values):
    return ("%.1f / %.1f" % (1000 * statistics.median(values), 1000 * max(values))) if values else "-"


class Health:
    """The counts and the last report_seconds of events, and the level rules above."""

    def __init__(self, max_residual, report_seconds=1.0, dark_seconds=3.0):
        """max_residual: the fail-safe's bound (cv2.lidarsgm.LidarFailSafe.maxResidual(), px)."""
        self.max_residual = float(max_residual)
        self.period, self.dark = float(report_seconds), float(dark_seconds)
        self.totals = Counter()     # since the start: lidar, alone:<class>, skipped:<class>, restarts, ...
        self.recent = deque()       # (time, key) of the events of the last period
        self.fusion_s = deque()     # (time, seconds) fusion and publishing of one set
        self.end_to_end_s = deque()  # (time, seconds) from a set's stamp to its outputs
        self.residual = None        # the newest matching residual (px)
        self.last_output = None     # the time of the last set that went out
        self.last_input = None      # the time of the last message
        self.reasons = {}           # key -> the newest reason text
        self.started = None
        self.lock = threading.RLock()  # the node's executor and worker threads both report

    def event(self, now, key, reason=""):
        with self.lock:
            self.totals[key] += 1
            self.recent.append((now, key))
            if reason:
                self.reasons[key] = reason

    def message_in(self, now):
        self.last_input = now
        if self.started is None:
            self.started = now

    def output(self, now, result, fusion_s, end_to_end_s):
        with self.lock:
            self.last_output = now
            self.event(now, "alone:" + result.stereo_alone if result.stereo_alone else "lidar", result.reason)
            self.fusion_s.append((now, fusion_s))
            self.end_to_end_s.append((now, end_to_end_s))
            if result.dropped_points:
                self.totals["non-finite points"] += result.dropped_points

    def _trim(self, now):
        for q in (self.recent, self.fusion_s, self.end_to_end_s):
            while q and q[0][0] < now - self.period:
                q.popleft()

    def level(self, now):
        """(level, message) by the rules of the module's docstring."""
        with self.lock:
            return self._level(now)

    def _level(self, now):
        self._trim(now)
        recent = Counter(k for _, k in self.recent)
        found = []  # (level, text) of every rule that applies, the worst first
        if self.last_input is not None and now - self.last_input < self.period:
            since = self.last_output if self.last_output is not None else self.started
            if since is not None and now - since >= self.dark:
                why = self.reasons.get("skipped:bad message", "") if recent["skipped:bad message"] else ""
                found.append((ERROR, "no output for %.1f s%s" % (now - since, ": " + why if why else
                                                                 " while messages arrive (no complete set of images)")))
        for cls in ALONE_CLASSES:
            if recent["alone:" + cls]:
                found.append((WARN, "stereo alone (%s): %s" % (cls, self.reasons.get("alone:" + cls, ""))))
        for key, text in (("skipped:bad message", "a set skipped (bad message)"),
                          ("skipped:overload", "sets skipped: input faster than the fusion"),
                          ("restart", "time went back (a bag loop or a clock reset): the synchroniser restarted")):
            if recent[key]:
                reason = self.reasons.get(key, "")
                found.append((WARN, text + (": " + reason if reason else "")))
        if self.residual is not None and self.residual > self.max_residual:
            found.append((WARN, "the LiDAR lies %.2f px from where the images match: check the calibration"
                          % self.residual))
        if self.last_input is None or now - self.last_input >= self.period:
            found.append((WARN, "no input"))
        if not found:
            return OK, "fused with the LiDAR"
        found.sort(key=lambda f: -f[0])
        return found[0][0], "; ".join(text for _, text in found)

    def values(self, now, extra=()):
        """[(key, value)] of a report: totals, then the last period's latencies, then extra."""
        with self.lock:
            return self._values(now, extra)

    def _values(self, now, extra):
        self._trim(now)
        t = self.totals
        out = [("sets fused with the LiDAR", t["lidar"])]
        out += [("stereo alone: " + cls, t["alone:" + cls]) for cls in ALONE_CLASSES]
        out += [("skipped: bad message", t["skipped:bad message"]), ("skipped: overload", t["skipped:overload"]),
                ("synchroniser restarts (time went back)", t["restart"]),
                ("non-finite points dropped", t["non-finite points"]),
                ("matching residual px (newest)", "-" if self.residual is None else "%.2f" % self.residual),
                ("fusion ms (median / max, last %.0f s)" % self.period, _ms([s for _, s in self.fusion_s])),
                ("end-to-end ms (median / max, last %.0f s)" % self.period, _ms([s for _, s in self.end_to_end_s]))]
        return out + list(extra)
