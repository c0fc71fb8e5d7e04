#!/usr/bin/env python
# This file is part of the lidarsgm module (an OpenCV extra module).
"""cv2.lidarsgm from Python: create, parameters, compute on a shipped KITTI frame, projection, semidensify."""

import os
import sys
import tempfile
import unittest

import numpy as np
import cv2 as cv

try:
    from tests_common import NewOpenCVTests
except ImportError:  # run outside OpenCV's python test tree
    NewOpenCVTests = unittest.TestCase


def data_dir():
    d = os.environ.get('OPENCV_PYTEST_LIDARSGM_DATA') or os.environ.get('OPENCV_TEST_DATA_PATH')
    if not d:
        raise unittest.SkipTest('OPENCV_TEST_DATA_PATH is not set')
    return d


class lidarsgm_test(NewOpenCVTests):

    def load_frame(self):
        d = os.path.join(data_dir(), 'kitti')
        f = cv.lidarsgm.loadKittiFrame(d, '000002')
        gt = cv.imread(os.path.join(d, 'disp_occ_0', '000002_10.png'), cv.IMREAD_UNCHANGED)
        return f.left, f.right, f.sparse, gt

    def test_confidence(self):
        left, right, sparse, _ = self.load_frame()
        m = cv.lidarsgm.StereoLidarSGM.create()
        disp = m.compute(left, right, sparse)
        disp2, conf = m.computeWithConfidence(left, right, sparse)
        np.testing.assert_array_equal(disp, disp2)
        self.assertEqual(conf.dtype, np.float32)
        self.assertTrue(np.all((conf >= 0) & (conf <= 1)))
        np.testing.assert_array_equal(conf == 0, disp == -16)
        gt = cv.imread(os.path.join(data_dir(), 'kitti', 'disp_occ_0', '000002_10.png'), cv.IMREAD_UNCHANGED)
        c = cv.lidarsgm.evaluateConfidence(disp, conf, gt)
        self.assertEqual(c.total(), cv.lidarsgm.evaluateDisparity(disp, gt).estimatedPixels)
        self.assertGreater(c.leastConfidentShare(0.1), 40)   # the errors gather in the least confident tenth
        self.assertLess(c.keptError(0.9), c.keptError(1.0))

    def test_datasets(self):
        d = os.path.join(data_dir(), 'kitti')
        c = cv.lidarsgm.readKittiCalibration(os.path.join(d, 'calib.txt'))
        self.assertEqual(c.projection.shape, (3, 4))
        self.assertEqual(c.lidarToCamera.shape, (4, 4))
        self.assertAlmostEqual(c.focalBaseline, 384.38148, places=9)   # P2[0,3] - P3[0,3]
        self.assertEqual(list(cv.lidarsgm.readKittiFrameIds(d)), ['000002', '000046'])
        f = cv.lidarsgm.loadKittiFrame(d, '000046', 4)   # every 4th ring: a 16-line LiDAR
        self.assertEqual(f.name, '000046')
        self.assertEqual(f.left.shape, f.right.shape)
        self.assertEqual(f.sparse.dtype, np.float32)
        self.assertEqual(f.groundTruth.shape, f.left.shape)
        self.assertAlmostEqual(f.calibration.focalBaseline, c.focalBaseline)
        scan = cv.lidarsgm.readVelodyneScan(os.path.join(d, 'velodyne', '000046.bin'))
        self.assertEqual(cv.lidarsgm.countLidarRings(scan), 64)
        png = cv.lidarsgm.encodeKittiDisparity(np.array([[-1, 0, 2.3125]], np.float32))
        np.testing.assert_array_equal(png, [[0, 0, 592]])
        with self.assertRaises(cv.error) as e:
            cv.lidarsgm.loadKittiFrame(d, '999999')
        self.assertIn('999999', str(e.exception))

    def test_point_clouds_of_other_writers(self):
        """readPointCloud against PCD files written by pypcd4 (every DATA kind, other field orders and types) and PLY
        files written by plyfile (ascii, both byte orders, a face element after the vertices)."""
        import pypcd4
        import plyfile
        rng = np.random.default_rng(7)
        n = 500
        xyz = (rng.standard_normal((n, 3)) * 20).astype(np.float32)
        intensity = rng.random(n).astype(np.float32)
        xyz[5] = np.nan
        xyz[17, 1] = np.inf
        keep = np.isfinite(xyz).all(1)
        clouds = [  # fields, types, columns
            (('x', 'y', 'z', 'intensity'), (np.float32,) * 4, [xyz[:, 0], xyz[:, 1], xyz[:, 2], intensity]),
            (('intensity', 'ring', 'z', 'x', 't', 'y'),
             (np.float32, np.uint16, np.float32, np.float32, np.float64, np.float32),
             [intensity, rng.integers(0, 64, n), xyz[:, 2], xyz[:, 0], rng.random(n), xyz[:, 1]]),
            (('x', 'y', 'z', 'intensity'), (np.float64, np.float64, np.float64, np.uint8),
             [xyz[:, 0], xyz[:, 1], xyz[:, 2], (intensity * 255).astype(np.uint8)]),
            (('x', 'y', 'z'), (np.float32,) * 3, [xyz[:, 0], xyz[:, 1], xyz[:, 2]]),
        ]
        with tempfile.TemporaryDirectory() as tmp:
            for c, (fields, types, cols) in enumerate(clouds):
                cols = [np.asarray(col).astype(t) for col, t in zip(cols, types)]
                pc = pypcd4.PointCloud.from_points(np.stack([col.astype(np.float64) for col in cols], 1), fields, types)
                for encoding in ('ascii', 'binary', 'binary_compressed'):
                    path = os.path.join(tmp, '%d_%s.pcd' % (c, encoding))
                    pc.save(path, encoding=pypcd4.Encoding(encoding))
                    if encoding == 'ascii':   # the values as the file writes them, parsed by numpy
                        with open(path) as f:
                            text = f.read().split('DATA ascii\n')[1]
                        cols = list(np.array(text.split(), np.float64).reshape(n, len(fields)).T)
                    byName = dict(zip(fields, cols))
                    expected = np.stack([byName['x'], byName['y'], byName['z'],
                                         byName.get('intensity', np.zeros(n))], 1).astype(np.float32)[keep]
                    np.testing.assert_array_equal(cv.lidarsgm.readPointCloud(path), expected, err_msg=path)
            vertices = np.empty(n, [('nx', 'f4'), ('x', 'f8'), ('y', 'f8'), ('z', 'f8'), ('intensity', 'u1')])
            vertices['nx'] = 1
            vertices['x'], vertices['y'], vertices['z'] = xyz[:, 0], xyz[:, 1], xyz[:, 2]
            vertices['intensity'] = (intensity * 255).astype(np.uint8)
            faces = np.empty(2, [('vertex_indices', object)])
            faces['vertex_indices'][0] = np.array([0, 1, 2], np.int32)
            faces['vertex_indices'][1] = np.array([3, 4, 5, 6], np.int32)
            for text, order in ((True, '='), (False, '<'), (False, '>')):
                path = os.path.join(tmp, 'cloud_%s.ply' % ('ascii' if text else 'le' if order == '<' else 'be'))
                plyfile.PlyData([plyfile.PlyElement.describe(vertices, 'vertex'),
                                 plyfile.PlyElement.describe(faces, 'face')], text=text, byte_order=order).write(path)
                v = plyfile.PlyData.read(path)['vertex'].data
                expected = np.stack([v['x'], v['y'], v['z'], v['intensity']], 1).astype(np.float32)[keep]
                np.testing.assert_array_equal(cv.lidarsgm.readPointCloud(path), expected, err_msg=path)
            bad = os.path.join(tmp, 'noz.pcd')
            with open(bad, 'w') as f:
                f.write('FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n')
            with self.assertRaises(cv.error) as e:
                cv.lidarsgm.readPointCloud(bad)
            self.assertIn('noz.pcd', str(e.exception))
            self.assertIn('FIELDS has no z', str(e.exception))

    def test_defaults_and_setters(self):
        m = cv.lidarsgm.StereoLidarSGM.create()
        self.assertEqual(m.getNumDisparities(), 128)
        self.assertEqual(m.getMode(), cv.lidarsgm.StereoLidarSGM_MODE_SDSGM)
        self.assertEqual(m.getConsistencyCheck(), cv.lidarsgm.StereoLidarSGM_CHECK_STEREO_LIDAR)
        self.assertAlmostEqual(m.getAlpha(), 0.7)
        m.setNumPaths(4)
        self.assertEqual(m.getNumPaths(), 4)
        with self.assertRaises(cv.error):
            m.setNumDisparities(100)

    def test_compute_kitti(self):
        left, right, sparse, gt = self.load_frame()
        self.assertEqual(sparse.dtype, np.float32)
        self.assertGreater(np.count_nonzero(sparse), 10000)
        m = cv.lidarsgm.StereoLidarSGM.create()
        disp = m.compute(left, right, sparse)
        self.assertEqual(disp.dtype, np.int16)
        self.assertEqual(disp.shape, left.shape)
        valid = (disp > -16) & (gt > 0)
        d = disp[valid] / 16.0
        g = gt[valid] / 256.0
        err = np.abs(d - g)
        bad = (err > 3) & (err > 0.05 * g)
        self.assertGreater(valid.sum() / (gt > 0).sum(), 0.95)   # coverage
        self.assertLess(bad.mean(), 0.05)                       # covered D1

        m.setOutputType(cv.CV_32F)
        disp32 = m.compute(left, right, sparse)
        self.assertEqual(disp32.dtype, np.float32)
        np.testing.assert_array_equal(disp32, disp.astype(np.float32) / 16)

        semi = m.semidensify(left, right, sparse)
        self.assertGreater(np.count_nonzero(semi > 0), np.count_nonzero(sparse > 0))

    def test_search_window(self):
        left, right, sparse, gt = self.load_frame()
        m = cv.lidarsgm.StereoLidarSGM.create()
        self.assertEqual(m.getSearchWindow(), 0)
        full = m.compute(left, right, sparse)
        self.assertEqual(m.getSearchedFraction(), 1.0)
        m.setSearchWindow(4)
        narrow = m.compute(left, right, sparse)
        self.assertLess(m.getSearchedFraction(), 0.5)
        valid = (full > -16) & (narrow > -16)
        self.assertGreater(np.mean(np.abs(full[valid].astype(int) - narrow[valid]) <= 16), 0.97)
        with self.assertRaises(cv.error):
            m.setSearchWindow(-1)

    def test_check_lidar(self):
        left, right, sparse, _ = self.load_frame()
        c = cv.lidarsgm.checkLidar(left, right, sparse)
        self.assertTrue(c.trusted)
        self.assertEqual(c.residual, cv.lidarsgm.matchingResidual(left, right, sparse))
        # The LiDAR 15 px below where it belongs (a pitch error of about a degree): condemned, and the move back found.
        low = np.zeros_like(sparse)
        low[15:] = sparse[:-15]
        c = cv.lidarsgm.checkLidar(left, right, low)
        self.assertFalse(c.trusted)
        self.assertGreater(c.residual, 1.0)
        self.assertLess(c.shiftedResidual, 0.8 * c.residual)
        self.assertLessEqual(abs(c.shift[1] + 15), 3)
        with self.assertRaises(cv.error):
            cv.lidarsgm.checkLidar(left, right, sparse, -1.0)
        # The fail-safe decides with checkLidar at its bound, and fuses the condemned frame as stereo alone.
        fail_safe = cv.lidarsgm.LidarFailSafe.create()
        self.assertEqual(cv.lidarsgm.LidarFailSafe.maxResidual(), 1.0)
        check = fail_safe.check(left, right, low)
        self.assertTrue(check.stereoAlone)
        self.assertEqual(check.residual, c.residual)
        m = cv.lidarsgm.StereoLidarSGM.create(numDisparities=64)
        check, disp = fail_safe.compute(m, left, right, low)
        self.assertTrue(check.stereoAlone)
        alone = cv.lidarsgm.LidarFailSafe.stereoAloneMatcher(m)
        self.assertEqual((alone.getMode(), alone.getConsistencyCheck()),
                         (cv.lidarsgm.StereoLidarSGM_MODE_SGM, cv.lidarsgm.StereoLidarSGM_CHECK_STEREO))
        np.testing.assert_array_equal(disp, alone.compute(left, right, np.zeros_like(low)))
        check, disp = cv.lidarsgm.LidarFailSafe.create(True).compute(m, left, right, low)
        self.assertFalse(check.stereoAlone or check.trusted)
        np.testing.assert_array_equal(disp, m.compute(left, right, low))

    def test_stereo_rig(self):
        K = np.array([[700.0, 0, 320], [0, 700, 240], [0, 0, 1]])
        D = np.array([[-0.2, 0.05, 0.0, 0.0, 0.0]])
        R = cv.Rodrigues(np.array([0.01, -0.01, 0.005]))[0]
        T = np.array([[-0.4], [0.0], [0.0]])
        l2l = np.array([[0, -1, 0, 0], [0, 0, -1, 0], [1, 0, 0, 0], [0, 0, 0, 1]], np.float64)
        rig = cv.lidarsgm.StereoRig.create(K, D, K, D, R, T, (640, 480), l2l)
        self.assertFalse(rig.isRectified())
        self.assertGreater(rig.getFocalBaseline(), 0)
        path = os.path.join(tempfile.mkdtemp(), 'rig.yml')
        rig.writeFile(path)
        again = cv.lidarsgm.StereoRig.fromFile(path)
        np.testing.assert_allclose(again.getProjectionLeft(), rig.getProjectionLeft(), atol=1e-9)
        img = np.random.RandomState(1).randint(0, 255, (480, 640), np.uint8)
        a, b = again.rectify(img, img)
        self.assertEqual(a.shape, img.shape)
        pts = np.array([[10.0, 0.5, 0.2, 0.0], [20.0, -1.0, 0.0, 0.0]], np.float32)
        sparse = again.projectCloud(pts)
        self.assertEqual(sparse.shape, (480, 640))
        self.assertEqual(np.count_nonzero(sparse), 2)
        self.assertAlmostEqual(float(sparse.max()), rig.getFocalBaseline() / 10.0, delta=0.2)
        with self.assertRaises(cv.error):
            cv.lidarsgm.StereoRig.fromFile(path + '.missing')

    def test_calibration_refinement(self):
        d = os.path.join(data_dir(), 'kitti')
        left, right, _, _ = self.load_frame()
        pts = cv.lidarsgm.readVelodyneScan(os.path.join(d, 'velodyne', '000002.bin'))
        calib = cv.lidarsgm.readKittiCalibration(os.path.join(d, 'calib.txt'))
        l2c = calib.lidarToCamera
        cal = cv.lidarsgm.LidarCalibration.create(calib.projection, calib.focalBaseline)
        cal.addFrame(left, right, pts)
        self.assertEqual(cal.getNumFrames(), 1)
        # A 0.5 degree pitch error: the residual grows, and the correction takes it back out.
        a = np.radians(0.5)
        err = np.eye(4)
        err[1:3, 1:3] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
        self.assertGreater(cal.residual(err @ l2c), 2 * cal.residual(l2c))
        exact = cal.refine(l2c)
        c = cal.refine(err @ l2c)
        self.assertEqual(c.lidarToCamera.shape, (4, 4))
        self.assertEqual(c.frames, 1)
        self.assertGreater(c.points, 5000)
        self.assertAlmostEqual(float(c.rotation[0] - exact.rotation[0]), -a, delta=np.radians(0.01))
        np.testing.assert_allclose(c.lidarToCamera, exact.lidarToCamera, atol=1e-3)
        self.assertLess(c.residualAfter, c.residualBefore)
        with self.assertRaises(cv.error):
            cv.lidarsgm.LidarCalibration.create(calib.projection, calib.focalBaseline).refine(l2c)   # no frames
        # The per-frame check from the images alone: the same error raises it above the DDC's Q1 band.
        size = (left.shape[1], left.shape[0])
        given = cv.lidarsgm.projectPointsToDisparity(pts, calib.projection, l2c, calib.focalBaseline, size)
        wrong = cv.lidarsgm.projectPointsToDisparity(pts, calib.projection, err @ l2c, calib.focalBaseline, size)
        self.assertLessEqual(cv.lidarsgm.matchingResidual(left, right, given), 1.0)
        self.assertGreater(cv.lidarsgm.matchingResidual(left, right, wrong), 1.0)
        with self.assertRaises(cv.error):
            cv.lidarsgm.matchingResidual(left, right, np.zeros_like(given))   # nothing to compare

    def test_save_load(self):
        m = cv.lidarsgm.StereoLidarSGM.create(numDisparities=64, P1=12, alpha=0.5)
        fd, path = tempfile.mkstemp(suffix='.yml')
        os.close(fd)
        try:
            m.save(path)
            n = cv.lidarsgm.StereoLidarSGM.load(path)
            self.assertEqual(n.getNumDisparities(), 64)
            self.assertEqual(n.getP1(), 12)
            self.assertAlmostEqual(n.getAlpha(), 0.5)
        finally:
            os.remove(path)

    def test_cuda_gpumat(self):
        if not hasattr(cv, 'cuda') or cv.cuda.getCudaEnabledDeviceCount() <= 0:
            self.skipTest('no CUDA device')
        left, right, sparse, _ = self.load_frame()
        m = cv.lidarsgm.StereoLidarSGM.create()
        cpu = m.compute(left, right, sparse)
        gl, gr, gs = cv.cuda_GpuMat(left), cv.cuda_GpuMat(right), cv.cuda_GpuMat(sparse)
        gd = cv.cuda.computeStereoLidarSGM(m, gl, gr, gs)
        self.assertIsInstance(gd, cv.cuda_GpuMat)
        np.testing.assert_array_equal(gd.download(), cpu)
        stream = cv.cuda_Stream()
        gd = cv.cuda.computeStereoLidarSGM(m, gl, gr, gs, stream=stream)
        stream.waitForCompletion()
        np.testing.assert_array_equal(gd.download(), cpu)
        semi = cv.cuda.semidensifyStereoLidarSGM(m, gl, gr, gs)
        np.testing.assert_array_equal(semi.download(), m.semidensify(left, right, sparse))
        # The projection on the GPU: every array a GpuMat, as the binding generator makes cv2.cuda's entry points.
        d = os.path.join(data_dir(), 'kitti')
        f = cv.lidarsgm.loadKittiFrame(d, '000002')
        c = f.calibration
        pts = cv.lidarsgm.readVelodyneScan(os.path.join(d, 'velodyne', '000002.bin'))
        g = cv.cuda.projectPointsToDisparity(cv.cuda_GpuMat(pts), cv.cuda_GpuMat(np.asarray(c.projection)),
                                             cv.cuda_GpuMat(np.asarray(c.lidarToCamera)), c.focalBaseline, c.imageSize)
        np.testing.assert_array_equal(g.download(), cv.lidarsgm.projectPointsToDisparity(
            pts, c.projection, c.lidarToCamera, c.focalBaseline, c.imageSize))

    def test_bad_input(self):
        m = cv.lidarsgm.StereoLidarSGM.create()
        colour = np.zeros((40, 60, 3), np.uint8)
        with self.assertRaises(cv.error) as ctx:
            m.compute(colour, colour, np.zeros((40, 60), np.float32))
        self.assertIn('COLOR_BGR2GRAY', str(ctx.exception))
        # numpy's default float64 for the sparse map: refused with the conversion that fixes it.
        grey = np.zeros((40, 60), np.uint8)
        with self.assertRaises(cv.error) as ctx:
            m.compute(grey, grey, np.zeros((40, 60), np.float64))
        self.assertIn('CV_64FC1', str(ctx.exception))
        self.assertIn('sparse.astype(numpy.float32)', str(ctx.exception))

    def test_units_and_messages(self):
        left, right, sparse, _ = self.load_frame()
        m = cv.lidarsgm.StereoLidarSGM.create()
        png = cv.lidarsgm.encodeKittiDisparity(sparse)        # uint16, disparity x 256
        with self.assertRaises(cv.error) as ctx:
            m.compute(left, right, png.astype(np.float32))    # the mistake: x256 as pixels
        msg = str(ctx.exception)
        self.assertIn('lie outside the search range [0, 128) px and beyond the image\'s width', msg)
        self.assertIn('divide it by 256', msg)
        self.assertNotIn('in function', msg)
        np.testing.assert_array_equal(m.compute(left, right, png),
                                      m.compute(left, right, png.astype(np.float32) / 256))
        with self.assertRaises(cv.error) as ctx:
            m.compute(left, right, None)
        self.assertIn('MODE_SGM with CHECK_STEREO', str(ctx.exception))
        self.assertNotIn('in function', str(ctx.exception))

    def test_create_takes_every_parameter_as_keyword(self):
        m = cv.lidarsgm.StereoLidarSGM.create(numPaths=4, medianSize=1, searchWindow=4, visibilityRadiusX=2,
                                              ringGapFactor=2.0, semidenseWeight=0.5, outputType=cv.CV_32F)
        self.assertEqual((m.getNumPaths(), m.getMedianSize(), m.getSearchWindow(), m.getVisibilityRadiusX()),
                         (4, 1, 4, 2))
        self.assertEqual((m.getRingGapFactor(), m.getSemidenseWeight(), m.getOutputType()), (2.0, 0.5, cv.CV_32F))
        d = cv.lidarsgm.StereoLidarSGM.create()
        self.assertEqual((d.getNumDisparities(), d.getP1(), d.getNumPaths(), d.getSearchWindow()), (128, 10, 8, 0))
        with self.assertRaises(cv.error) as ctx:
            cv.lidarsgm.StereoLidarSGM.create(numPaths=6)
        self.assertIn('numPaths', str(ctx.exception))
        # Every function and method of the module says what it does beyond its signature (the header's doxygen, as
        # OpenCV's generator carries it; Algorithm's own methods aside).
        def described(f):
            doc = f.__doc__ or ''
            return len(' '.join(line for line in doc.splitlines()[1:] if line.strip(' .'))) > 10
        inherited = set(dir(cv.Algorithm))
        for name in dir(cv.lidarsgm):
            o = getattr(cv.lidarsgm, name)
            if name.startswith('_') or not callable(o):
                continue
            if not isinstance(o, type):
                self.assertTrue(described(o), '%s has no docstring: %r' % (name, o.__doc__))
                continue
            for method in dir(o):
                f = getattr(o, method)
                if method.startswith('_') or method in inherited or isinstance(f, type) or not callable(f):
                    continue
                self.assertTrue(described(f), '%s.%s has no docstring: %r' % (name, method, f.__doc__))

    def test_typing_stubs_beside_cv2(self):
        # The stubs lie beside the cv2 that is imported (python_loader/ of the build, or an installed venv), where
        # mypy and editors look; mypy checks a snippet against them.
        stubs = os.path.join(os.path.dirname(cv.__file__), 'lidarsgm', '__init__.pyi')
        self.assertTrue(os.path.isfile(stubs), stubs)
        try:
            from mypy import api
        except ImportError:
            raise unittest.SkipTest('mypy is not installed')
        d = tempfile.mkdtemp()
        snippet = os.path.join(d, 'snippet.py')
        with open(snippet, 'w') as f:
            f.write('import cv2\n'
                    'm = cv2.lidarsgm.StereoLidarSGM.create(numPaths=4)\n'
                    'n: int = m.getNumPaths()\n'
                    'bad: str = m.getNumPaths()\n')
        out, err, rc = api.run([snippet, '--no-incremental', '--cache-dir', os.path.join(d, 'cache'),
                                '--python-executable', sys.executable])
        self.assertNotIn('Cannot find implementation or library stub', out)
        self.assertIn('snippet.py:4: error: Incompatible types in assignment', out)
        self.assertNotIn('snippet.py:3', out)

    def test_parameter_file_with_a_misspelt_key(self):
        params = os.environ.get('LIDARSGM_PARAMS')
        if not params:
            raise unittest.SkipTest('LIDARSGM_PARAMS is not set')
        with open(os.path.join(params, 'kitti_best.yml')) as f:
            text = f.read().replace('edgeThreshold:', 'edgeTreshold:')
        path = os.path.join(tempfile.mkdtemp(), 'typo.yml')
        with open(path, 'w') as f:
            f.write(text)
        with self.assertRaises(cv.error) as ctx:
            cv.lidarsgm.StereoLidarSGM.load(path)
        self.assertIn("unknown key 'edgeTreshold'", str(ctx.exception))
        self.assertIn("did you mean 'edgeThreshold'", str(ctx.exception))
        self.assertIn(path, str(ctx.exception))

    def params_file(self, text):
        path = os.path.join(tempfile.mkdtemp(), 'params.yml')
        with open(path, 'w') as f:
            f.write(text)
        return path

    def load_error(self, text):
        """What load() raises for a parameter file of this text."""
        with self.assertRaises(cv.error) as ctx:
            cv.lidarsgm.StereoLidarSGM.load(self.params_file(text))
        return str(ctx.exception)

    def test_parameter_file_key_as_near_to_two_names(self):
        # 3 edits from both minDisparity and numDisparities: the one that starts the same way is meant.
        said = self.load_error('%YAML:1.0\n---\nlidarsgm_StereoLidarSGM:\n   numDisparity: 64\n')
        self.assertIn("did you mean 'numDisparities'", said)

    def test_parameter_file_without_its_node(self):
        said = self.load_error('%YAML:1.0\n---\nnumDisparities: 64\nP1: 10\n')
        self.assertIn('has its keys at the top level: they go under a node lidarsgm_StereoLidarSGM:', said)

    def test_parameter_file_without_the_yaml_line(self):
        path = self.params_file('lidarsgm_StereoLidarSGM:\n   numDisparities: 64\n')
        try:
            m = cv.lidarsgm.StereoLidarSGM.load(path)
        except cv.error as e:   # OpenCV 4's parser needs the line
            self.assertIn('a YAML file starts with the line %YAML:1.0', str(e))
        else:                   # OpenCV 5's reads the file without it
            self.assertEqual(m.getNumDisparities(), 64)


if __name__ == '__main__':
    NewOpenCVTests.bootstrap()
