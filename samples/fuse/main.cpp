// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

// lidarsgm_fuse: fuse a stereo pair with LiDAR into a dense disparity map, for one frame or a whole dataset folder,
// and score it against ground truth with the KITTI devkit's rules (D1) or Middlebury's bad-N.
//
//   lidarsgm_fuse --kitti-frame DIR --id 000002 [--out OUT]      one frame of a KITTI-layout folder (raw scan)
//   lidarsgm_fuse --left L --right R (--sparse S | --velodyne V --calib C) [--gt G] [--out OUT]
//   lidarsgm_fuse --rig RIG.yml --left L --right R --points P.pcd [--out OUT]   raw pair of your own rig
//   lidarsgm_fuse --rig-folder DIR [--out OUT] [--resume]       every frame of your own rig's recording
//   lidarsgm_fuse --kitti DIR [--table5] [--lidar-lines 64,32,16]   every frame listed in DIR/frames.txt
//   lidarsgm_fuse --kitti-raw DRIVE [--gt-depth DIR] --out OUT --format depth,ply   every frame of a raw drive
//   lidarsgm_fuse --middlebury DIR [--seed N]                   every scene folder in DIR (1 % of GT as input)
// Run with --help for every option.

#include "tool.hpp"
#include <cstdio>

using namespace cv;
using namespace lidarsgm_fuse;

namespace {

//! The single frame the options name.
Frame loadFrame(const Options& o)
{
    Frame f;
    const LidarRings rings = lidarRings(o, lidarLineCounts(o).front());   // the scan's rings, where a scan is read
    if (o.has("kitti-frame"))
    {
        f = lidarsgm::loadKittiFrame(o.str("kitti-frame"), o.str("id", "000002"), rings.every, rings.first);
        if (o.has("resize"))
        {
            // Speed runs at other sizes: the frame scaled (LiDAR disparities scaled with the width).
            int w = 0, h = 0;
            sscanf(o.str("resize").c_str(), "%dx%d", &w, &h);
            const double sx = (double)w / f.left.cols;
            resize(f.left, f.left, Size(w, h), 0, 0, INTER_LINEAR);
            resize(f.right, f.right, Size(w, h), 0, 0, INTER_LINEAR);
            resize(f.sparse, f.sparse, Size(w, h), 0, 0, INTER_NEAREST);
            f.sparse *= sx;
            f.groundTruth.release();
        }
        return f;
    }
    f.name = o.str("left");
    f.leftImage = readImage(o.str("left"));
    f.left = toGrey(f.leftImage);
    f.right = readGrey(o.str("right"));
    if (o.has("rig"))
    {
        // Your own rig: the raw pair rectified, the cloud projected into the rectified left view.
        const Ptr<lidarsgm::StereoRig> rig = lidarsgm::StereoRig::fromFile(o.str("rig"));
        Mat leftRect, rightRect;
        rig->rectify(f.leftImage, f.right, leftRect, rightRect);
        f.leftImage = leftRect;
        f.left = toGrey(leftRect);
        f.right = rightRect;
        const Mat cloud = lidarsgm::readPointCloud(o.has("points") ? o.str("points") : o.str("velodyne"));
        rig->projectCloud(cloud, f.sparse);
        f.calibration = rig->getCalibration();
    }
    else if (o.has("points") && o.has("calib"))
    {
        f.calibration = lidarsgm::readKittiCalibration(o.str("calib"));
        const lidarsgm::KittiCalibration& c = f.calibration;
        lidarsgm::projectPointsToDisparity(lidarsgm::readPointCloud(o.str("points")), c.projection, c.lidarToCamera,
                                           c.focalBaseline, f.left.size(), f.sparse);
    }
    else if (o.has("sparse"))
    {
        f.sparse = readImage(o.str("sparse"), "sparse disparity");
        if (o.has("calib"))
            f.calibration = lidarsgm::readKittiCalibration(o.str("calib"));
    }
    else if (o.has("velodyne") && o.has("calib"))
    {
        f.calibration = lidarsgm::readKittiCalibration(o.str("calib"));
        const lidarsgm::KittiCalibration& c = f.calibration;
        lidarsgm::projectPointsToDisparity(
            lidarsgm::selectLidarRings(lidarsgm::readVelodyneScan(o.str("velodyne")), rings.every, rings.first),
            c.projection, c.lidarToCamera, c.focalBaseline, f.left.size(), f.sparse);
    }
    if (o.has("gt"))
        f.groundTruth = lidarsgm::readKittiDisparity(o.str("gt"));
    return f;
}

} // namespace

int main(int argc, char** argv)
{
    Options o;
    bool help = false;
    if (const int rc = parseCommandLine(argc, argv, o, help))
        return rc;
    if (help)
    {
        printHelp();
        return 0;
    }
    if (const int rc = checkOptions(o))
        return rc;
    try
    {
        if (o.has("threads"))
            setNumThreads(o.i("threads", -1));
        if (o.has("kitti"))
            return runKittiFolder(o);
        if (o.has("kitti-raw"))
            return runKittiRaw(o);
        if (o.has("rig-folder"))
            return runRigFolder(o);
        if (o.has("middlebury"))
            return runMiddlebury(o);
        Frame f = loadFrame(o);
        return runFrame(o, f);
    }
    catch (const cv::Exception& e)
    {
        fprintf(stderr, "lidarsgm_fuse: error: %s\n", e.err.c_str());
        return 1;
    }
}
