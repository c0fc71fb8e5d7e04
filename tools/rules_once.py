#!/usr/bin/env python3
"""The rules the whole tree states once: lists every place that states one of them again; exits 1 when there is one.

- The fail-safe's bound on the matching residual (1 px) is defined in src/fail_safe.cpp alone
  (cv::lidarsgm::LidarFailSafe::maxResidual()): no other product file gives a residual bound a value, passes one to
  checkLidar, or calls checkLidar where it decides a frame (the front ends ask LidarFailSafe).
- The stereo-alone fallback (the matcher's settings in MODE_SGM, the LiDAR's check dropped) is written in
  src/fail_safe.cpp alone (LidarFailSafe::stereoAloneMatcher): no other product file sets MODE_SGM or
  CHECK_STEREO on a matcher of its own.

    tools/rules_once.py      (run from anywhere)

Product files: src/, src_cuda/, include/, samples/, ros2/lidarsgm_ros/, tools/ (C++, CUDA, Python); tests may state
values of their own. A scanner of lines, comments left out."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDERS = ("src", "src_cuda", "include", "samples", os.path.join("ros2", "lidarsgm_ros"), "tools")
EXTENSIONS = (".cpp", ".hpp", ".cu", ".cuh", ".h", ".py")
HOME = os.path.join("src", "fail_safe.cpp")
# checkLidar measured, not decided with: the benchmark of the check itself.
MEASURES = {os.path.join("tools", "fail_safe_benchmark.py")}

# (rule, pattern, where it may stand)
RULES = [
    ("the residual bound", re.compile(r"(?i)\b\w*max_?\w*residual\w*\s*=\s*(?:[1-9]\d*(?:\.\d*)?|0?\.\d*[1-9]\d*)\b"),
     {HOME}),
    ("the residual bound", re.compile(r"\b(?:kMaxLidarResidual|MAX_MATCHING_RESIDUAL)\b"), set()),
    ("the residual bound", re.compile(r"\bcheckLidar\s*\([^()]*,[^()]*,[^()]*,\s*[\d.]+"), set()),
    ("the fail-safe's decision", re.compile(r"\bcheckLidar\s*\("), None),   # None: the library and MEASURES
    ("the stereo-alone fallback", re.compile(r"setMode\s*\([^()]*MODE_SGM\b|\bmatcher\s*\(\s*Matcher::MODE_SGM\b|"
                                             r"_mode\s*\(\s*[\"']sgm[\"']\s*\)"), {HOME}),
    ("the stereo-alone fallback", re.compile(r"setConsistencyCheck\s*\([^()]*CHECK_STEREO\s*\)"), {HOME}),
]


def code_lines(path):
    """(number, text) of a file's lines, comments and docstring-free enough for the patterns: // and # comments
    dropped, and the lines of C block comments and Python triple-quoted strings."""
    py = path.endswith(".py")
    block = False
    with open(path, encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            s = line
            if py:
                quotes = s.count('"""') + s.count("'''")
                if block or quotes:
                    if quotes % 2:
                        block = not block
                    continue
                s = s.split("#", 1)[0] if not re.search(r"[\"'][^\"']*#", s) else s
            else:
                if block:
                    if "*/" in s:
                        block = False
                    continue
                if "/*" in s and "*/" not in s:
                    block = True
                    s = s.split("/*", 1)[0]
                s = re.sub(r"/\*.*?\*/", "", s)
                s = s.split("//", 1)[0]
            yield n, s


def main():
    found = []
    for folder in FOLDERS:
        for base, _, files in os.walk(os.path.join(ROOT, folder)):
            for name in sorted(files):
                if not name.endswith(EXTENSIONS):
                    continue
                path = os.path.join(base, name)
                rel = os.path.relpath(path, ROOT)
                if rel == os.path.join("tools", "rules_once.py"):
                    continue
                for n, text in code_lines(path):
                    for rule, pattern, allowed in RULES:
                        if not pattern.search(text):
                            continue
                        library = rel.startswith(("src" + os.sep, "include" + os.sep))
                        ok = (library or rel in MEASURES) if allowed is None else rel in allowed
                        if not ok:
                            found.append("%s:%d: %s stated again: %s" % (rel, n, rule, text.strip()))
    homes = sum(1 for n, t in code_lines(os.path.join(ROOT, HOME)) if RULES[0][1].search(t))
    if homes != 1:
        found.append("%s: the residual bound defined %d times, expected once" % (HOME, homes))
    for line in found:
        print(line)
    print("%d place(s) state a rule that src/fail_safe.cpp states" % len(found) if found else
          "every rule stated once (src/fail_safe.cpp)")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
