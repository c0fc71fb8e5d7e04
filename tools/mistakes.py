#!/usr/bin/env python3
"""The mistakes a newcomer makes, each made once, and what the module or the tool says: the table of
doc/mistakes.md, printed as Markdown rows. The test test/tool_and_python/test_mistakes.py runs this and checks that
the doc holds every row as printed, so the doc shows what a user sees today.

    PYTHONPATH=<OpenCV build>/python_loader python3 tools/mistakes.py --tool <OpenCV build>/bin/lidarsgm_fuse

Run from the repository root (it reads testdata/ and doc/params/). Files it writes go to a temporary folder, shown
as <tmp> in the table.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
import cv2 as cv

KITTI = os.path.join('testdata', 'kitti')


def cv_message(call):
    """The text of the cv.error that call raises (its err: what a Python user reads after 'error: (code:name)')."""
    try:
        call()
    except cv.error as e:
        return e.err
    return '(nothing raised)'


def logged(code):
    """What a snippet run in a fresh interpreter writes to OpenCV's log (stderr): warnings and notices."""
    out = subprocess.run([sys.executable, '-c', 'import cv2 as cv, numpy as np\n' + code], capture_output=True,
                         text=True, env=dict(os.environ, OPENCV_LOG_LEVEL='WARNING'))
    lines = [ln for ln in out.stderr.splitlines() if 'lidarsgm' in ln]
    return lines[0].split('] ', 1)[-1] if lines else '(nothing said)'


def rows(tool, tmp):
    frame = cv.lidarsgm.loadKittiFrame(KITTI, '000002')
    left, right, sparse = frame.left, frame.right, frame.sparse
    m = cv.lidarsgm.StereoLidarSGM.create()
    png = cv.lidarsgm.encodeKittiDisparity(sparse)          # KITTI's encoding: uint16, disparity x 256
    yield ("KITTI's disparity PNG (uint16, x 256) cast to float32 and passed as pixels",
           cv_message(lambda: m.compute(left, right, png.astype(np.float32))))
    yield ('SDSGM (the default) without a sparse map',
           cv_message(lambda: m.compute(left, right, None)))
    yield ('A sparse map with no usable value (all NaN: a projection gone wrong)',
           logged('m = cv.lidarsgm.StereoLidarSGM.create()\n'
                  'f = cv.lidarsgm.loadKittiFrame(%r, "000002")\n'
                  'm.compute(f.left, f.right, np.full(f.sparse.shape, np.nan, np.float32))' % KITTI))
    yield ('Colour images', cv_message(lambda: m.compute(frame.leftImage, frame.leftImage, sparse)))
    yield ("numpy's float64 for the sparse map", cv_message(lambda: m.compute(left, right, sparse.astype(np.float64))))
    best = open(os.path.join('doc', 'params', 'kitti_best.yml')).read()

    def loaded(name, text):
        """What StereoLidarSGM.load says of a parameter file <tmp>/name of this text."""
        path = os.path.join(tmp, name)
        with open(path, 'w') as f:
            f.write(text)
        return cv_message(lambda: cv.lidarsgm.StereoLidarSGM.load(path))
    yield ('A misspelt key in a parameter file (`edgeTreshold`)',
           loaded('typo.yml', best.replace('edgeThreshold:', 'edgeTreshold:')))
    yield ('A value out of range in a parameter file (`numPaths: 6`)',
           loaded('bad_value.yml', best.replace('numPaths: 8', 'numPaths: 6')))
    yield ('A parameter file that does not exist',
           cv_message(lambda: cv.lidarsgm.StereoLidarSGM.load(os.path.join(tmp, 'kitti_bset.yml'))))
    yield ('A malformed parameter file (an unclosed `[`)',
           loaded('broken.yml', '%YAML:1.0\n---\nlidarsgm_StereoLidarSGM:\n   P1: 10\n   P2: [120\n   Q1: 5\n'))
    yield ('A misspelt key as near to two names (`numDisparity`: 3 edits from `minDisparity` too)',
           loaded('near.yml', best.replace('numDisparities:', 'numDisparity:')))
    yield ('A parameter file written by hand with its keys at the top level',
           loaded('flat.yml', '%YAML:1.0\n---\nnumDisparities: 64\nsearchWindow: 4\n'))
    yield ('An unknown keyword of `create()` (`numPath`)', type_error(lambda: cv.lidarsgm.StereoLidarSGM.create(numPath=4)))
    rig = os.path.join(tmp, 'rig.yml')
    fs = cv.FileStorage(rig, cv.FILE_STORAGE_WRITE)
    fs.write('image_width', 1242)
    fs.write('image_height', 375)
    fs.write('P1', frame.calibration.projection)
    fs.write('P2', frame.calibration.rightProjection)
    fs.write('lidar_to_lft', frame.calibration.lidarToCamera)
    fs.release()
    yield ('A misspelt key in a rig file (`lidar_to_lft`)', cv_message(lambda: cv.lidarsgm.StereoRig.fromFile(rig)))
    pcd = os.path.join(tmp, 'scan.pcd')
    with open(pcd, 'w') as f:
        f.write('VERSION 0.7\nFIELDS x y z ring_id\nSIZE 4 4 4 2\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\n'
                'POINTS 1\nDATA ascii\n1 2 3 17\n')
    yield ('A PCD cloud whose fourth field is `ring_id`, not `intensity`',
           logged('cv.lidarsgm.readPointCloud(%r)' % pcd))
    for what, args in tool_cases(tmp):
        out = subprocess.run([tool] + args, capture_output=True, text=True)
        said = [ln for ln in out.stderr.splitlines() if ln.strip()]
        yield (what, '%s (exit %d)' % (said[-1] if said else '(nothing said)', out.returncode))


def type_error(call):
    try:
        call()
    except TypeError as e:
        return str(e)
    return '(nothing raised)'


def tool_cases(tmp):
    """The tool's command-line mistakes: (what, arguments)."""
    out = os.path.join(tmp, 'out')
    left = os.path.join(KITTI, 'image_2', '000002_10.png')
    right = os.path.join(KITTI, 'image_3', '000002_10.png')
    return [
        ('Tool: `--sparse` beside `--kitti-frame`',
         ['--kitti-frame', KITTI, '--sparse', os.path.join(KITTI, 'disp_occ_0', '000002_10.png'), '--out', out]),
        ('Tool: `--left` / `--right` and no LiDAR', ['--left', left, '--right', right, '--out', out]),
        ('Tool: `--left` / `--right` beside `--kitti-frame`', ['--kitti-frame', KITTI, '--left', left, '--right', right]),
        ('Tool: `--table5` on one frame', ['--kitti-frame', KITTI, '--table5']),
        ('Tool: `--velodyne` without a calibration',
         ['--left', left, '--right', right, '--velodyne', os.path.join(KITTI, 'velodyne', '000002.bin')]),
        ('Tool: `--resume` with nothing to resume', ['--kitti', KITTI, '--resume']),
        ('Tool: a size without its height', ['--kitti-frame', KITTI, '--resize', '100']),
        ('Tool: a word where a number belongs', ['--kitti-frame', KITTI, '--num-disparities', 'abc']),
        ('Tool: a parameter out of range', ['--kitti-frame', KITTI, '--paths', '6']),
        ('Tool: a misspelt option', ['--kitti-frame', KITTI, '--serch-window', '4']),
        ('Tool: a frame that is not there', ['--kitti-frame', KITTI, '--id', '000003']),
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--tool', required=True, help='the lidarsgm_fuse binary')
    args = ap.parse_args()
    tmp = tempfile.mkdtemp()
    print('| mistake | what you are told |')
    print('| --- | --- |')
    for what, said in rows(args.tool, tmp):
        said = said.replace(tmp, '<tmp>').replace('|', '\\|').strip()
        print('| %s | %s |' % (what, said))


if __name__ == '__main__':
    main()
