#!/usr/bin/env python3
# This file is part of the lidarsgm module (an OpenCV extra module).
"""Every ```python block of README.md and doc/*.md runs as written: a file's blocks top to bottom in one fresh
interpreter (shared globals), from the repository root, with the build's cv2. A failure names the file, the block
and the Markdown line; the snippets may write only into the temporary folder (TMPDIR), never into the repository.

Environment (set by ctest): PYTHONPATH with the OpenCV build's python_loader.
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

from doc_blocks import ROOT, blocks, doc_files

# Runs in the child: each block compiled under the Markdown file's name with its own line numbers, so that a
# traceback shows the doc's line.
DRIVER = r"""
import json, sys, traceback
job = json.load(sys.stdin)
scope = {"__name__": "__main__"}
for i, (line, code) in enumerate(job["blocks"], 1):
    print("--- %s, python block %d of %d (line %d)" % (job["path"], i, len(job["blocks"]), line), flush=True)
    try:
        exec(compile("\n" * (line - 1) + code, job["file"], "exec"), scope)
    except BaseException:
        sys.stdout.flush()
        traceback.print_exc()
        print("FAILED: %s, python block %d (line %d)" % (job["path"], i, line), file=sys.stderr)
        sys.exit(1)
"""


def repository_files():
    """Every file under the repository root but .git and the build folders (those holding a CMakeCache.txt)."""
    files = set()
    for top, dirs, names in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d != ".git" and not os.path.isfile(os.path.join(top, d, "CMakeCache.txt"))]
        files.update(os.path.join(top, n) for n in names)
    return files


class PythonSnippetsTest(unittest.TestCase):
    def test_blocks_run_as_written(self):
        files = [(f, blocks(f, "python")) for f in doc_files()]
        files = [(f, b) for f, b in files if b]
        self.assertIn("README.md", [f for f, _ in files])
        self.assertIn(os.path.join("doc", "tutorial.md"), [f for f, _ in files])
        before = repository_files()
        for path, found in files:
            with self.subTest(path=path), tempfile.TemporaryDirectory() as tmp:
                env = dict(os.environ, TMPDIR=tmp, PYTHONDONTWRITEBYTECODE="1")
                job = json.dumps({"path": path, "file": os.path.join(ROOT, path), "blocks": found})
                p = subprocess.run([sys.executable, "-c", DRIVER], input=job, cwd=ROOT, env=env,
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                                   timeout=900)
                sys.stdout.write(p.stdout)
                self.assertEqual(p.returncode, 0, "%s: a python block failed:\n%s" % (path, p.stdout))
        written = sorted(os.path.relpath(f, ROOT) for f in repository_files() - before)
        self.assertEqual(written, [], "the snippets wrote into the repository (write into tempfile.mkdtemp())")


if __name__ == "__main__":
    unittest.main()
