#!/usr/bin/env python3
# This file is part of the lidarsgm module (an OpenCV extra module).
"""Every ```cpp block of README.md and doc/*.md compiles against an installed OpenCV, and runs from the repository
root on the shipped data, as a user builds it: the OpenCV build installed into a prefix, a project that finds it
with CMAKE_PREFIX_PATH and find_package(OpenCV REQUIRED lidarsgm), and the README's compiler line.

A block with a main() is a program of its own; a file's other blocks are fragments that run in one main(), in order,
after the includes the tutorial names. Each block carries #line directives, so that a compiler error names the
Markdown file and line. The README program's output must show the figures the README states for it.

Environment (set by ctest): LIDARSGM_OPENCV_BUILD (the OpenCV build folder), LIDARSGM_WORK (scratch),
LIDARSGM_CMAKE (the cmake to use).
"""
import glob
import os
import re
import shutil
import subprocess
import unittest

from doc_blocks import ROOT, blocks, doc_files

BUILD = os.environ.get("LIDARSGM_OPENCV_BUILD", "")
WORK = os.environ.get("LIDARSGM_WORK", "")
CMAKE = os.environ.get("LIDARSGM_CMAKE", "cmake")
# The includes doc/tutorial.md names for its blocks.
FRAGMENT_HEADER = ("#include <opencv2/lidarsgm.hpp>\n#include <opencv2/lidarsgm/datasets.hpp>\n"
                   "#include <opencv2/lidarsgm/evaluation.hpp>\n#include <opencv2/lidarsgm/calibration.hpp>\n"
                   "#include <opencv2/lidarsgm/rig.hpp>\n#include <opencv2/imgcodecs.hpp>\n#include <opencv2/imgproc.hpp>\n\n"
                   "int main()\n{\n")
CONSUMER = """cmake_minimum_required(VERSION 3.16)
project(lidarsgm_doc_snippets CXX)
find_package(OpenCV REQUIRED lidarsgm)
message(STATUS "lidarsgm snippets: OpenCV ${OpenCV_VERSION} from ${OpenCV_DIR}")
foreach(program %s)
  add_executable(${program} ${program}.cpp)
  target_link_libraries(${program} PRIVATE ${OpenCV_LIBS})
endforeach()
"""
# The figures the README gives for its program: "./fuse    # 000002: coverage 99.84 %, total D1 1.77 %, then
# kitti_best.yml's 1.27 %".
README_FIGURES = re.compile(r"^\s*\./fuse\s+#\s*000002: coverage ([\d.]+) %, total D1 ([\d.]+) %, then kitti_best\.yml's "
                            r"([\d.]+) %", re.M)
PROGRAM_FIGURES = re.compile(r"000002: coverage ([\d.]+) %, total D1 ([\d.]+) %\nkitti_best\.yml: total D1 ([\d.]+) %")


def run(cmd, cwd=None, timeout=900):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                       timeout=timeout)
    return p.returncode, p.stdout


def line_directive(line, path):
    return '#line %d "%s"\n' % (line, path)


def programs():
    """(name, Markdown file, source) of every program the cpp blocks make."""
    made = []
    for path in doc_files():
        found = blocks(path, "cpp")
        stem = re.sub(r"\W", "_", os.path.splitext(path)[0])
        fragments = ""
        for i, (line, code) in enumerate(found, 1):
            if re.search(r"\bint\s+main\s*\(", code):
                made.append(("%s_block%d" % (stem, i), path, line_directive(line, path) + code))
            else:
                fragments += line_directive(line, path) + code
        if fragments:
            made.append(("%s_fragments" % stem, path, FRAGMENT_HEADER + fragments + "return 0;\n}\n"))
    return made


@unittest.skipUnless(BUILD and WORK, "run by ctest (LIDARSGM_OPENCV_BUILD, LIDARSGM_WORK)")
class CppSnippetsTest(unittest.TestCase):
    def test_blocks_compile_against_the_install_and_run(self):
        made = programs()
        self.assertIn("README.md", [path for _, path, _ in made])
        shutil.rmtree(WORK, ignore_errors=True)
        src, prefix = os.path.join(WORK, "src"), os.path.join(WORK, "prefix")
        os.makedirs(src)
        for name, _, code in made:
            with open(os.path.join(src, name + ".cpp"), "w") as f:
                f.write(code)
        with open(os.path.join(src, "CMakeLists.txt"), "w") as f:
            f.write(CONSUMER % " ".join(name for name, _, _ in made))

        rc, out = run([CMAKE, "--install", BUILD, "--prefix", prefix])
        self.assertEqual(rc, 0, out)
        rc, out = run([CMAKE, "-S", src, "-B", os.path.join(WORK, "build"), "-G", "Ninja",
                       "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_PREFIX_PATH=" + prefix])
        self.assertEqual(rc, 0, out)
        found = re.search(r"lidarsgm snippets: OpenCV \S+ from (.*)", out)
        self.assertTrue(found and found.group(1).startswith(prefix), out)   # the install, no other OpenCV
        rc, out = run([CMAKE, "--build", os.path.join(WORK, "build")])
        self.assertEqual(rc, 0, "a cpp block does not compile:\n" + out)

        # The README's compiler line: the installed headers and libraries, no CMake.
        readme = [(name, code) for name, path, code in made if path == "README.md" and "_block" in name]
        self.assertEqual(len(readme), 1, "README.md: one cpp block with a main()")
        include = glob.glob(os.path.join(prefix, "include", "opencv[0-9]*"))
        libdir = [os.path.dirname(p) for p in glob.glob(os.path.join(prefix, "lib*", "libopencv_core.so"))]
        self.assertEqual(len(include), 1, include)
        self.assertEqual(len(libdir), 1, libdir)
        direct = os.path.join(WORK, "fuse")
        rc, out = run(["c++", os.path.join(src, readme[0][0] + ".cpp"), "-o", direct, "-I" + include[0],
                       "-L" + libdir[0], "-Wl,-rpath," + libdir[0], "-lopencv_lidarsgm", "-lopencv_core"])
        self.assertEqual(rc, 0, "README.md's program with the compiler line:\n" + out)

        with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
            stated = README_FIGURES.search(f.read())
        self.assertTrue(stated, "README.md: no './fuse    # 000002: coverage ...' line")
        for name, path, _ in made:
            for program in [os.path.join(WORK, "build", name)] + ([direct] if name == readme[0][0] else []):
                with self.subTest(program=program):
                    rc, out = run([program], cwd=ROOT)
                    print("%s (%s):\n%s" % (os.path.basename(program), path, out))
                    self.assertEqual(rc, 0, "%s: the program of its cpp block(s) failed:\n%s" % (path, out))
                    if name == readme[0][0]:
                        figures = PROGRAM_FIGURES.search(out)
                        self.assertTrue(figures, out)
                        self.assertEqual(figures.groups(), stated.groups(),
                                         "README.md states other figures for its program than it prints")


if __name__ == "__main__":
    unittest.main()
