// This file is part of the lidarsgm module (an OpenCV extra module).
// It is subject to the license terms in the LICENSE file found in the top-level directory of this distribution.

#ifndef OPENCV_LIDARSGM_DATASETS_HPP
#define OPENCV_LIDARSGM_DATASETS_HPP

#include "opencv2/core.hpp"

namespace cv {
namespace lidarsgm {

//! @addtogroup lidarsgm
//! @{

/** @brief The calibration of a KITTI stereo pair with its Velodyne: the file's matrices as they are, and what
projectPointsToDisparity takes (projection, lidarToCamera, focalBaseline).
 */
struct CV_EXPORTS_W_SIMPLE KittiCalibration
{
    CV_WRAP KittiCalibration() : focalBaseline(0) {}
    //! The rectified left camera's 3x4 projection matrix, CV_64F (P2, or P_rect_02 in the raw data).
    CV_PROP_RW Mat projection;
    //! The rectified right camera's 3x4 projection matrix, CV_64F (P3, or P_rect_03 in the raw data).
    CV_PROP_RW Mat rightProjection;
    //! The rectifying rotation of the reference camera, 3x3 CV_64F (R0_rect, or R_rect_00 in the raw data).
    CV_PROP_RW Mat rectification;
    //! The LiDAR-to-camera transform before rectification, 3x4 CV_64F [R | t] (Tr_velo_to_cam, or R and T of
    //! calib_velo_to_cam.txt in the raw data).
    CV_PROP_RW Mat veloToCamera;
    //! The LiDAR-to-rectified-camera transform, 4x4 CV_64F: rectification * veloToCamera.
    CV_PROP_RW Mat lidarToCamera;
    //! Focal length in pixels times the baseline in metres: P2[0,3] - P3[0,3].
    CV_PROP_RW double focalBaseline;
    /** The rectified images' size: S_rect_02 of a raw drive's calib_cam_to_cam.txt; KITTI 2015's calib.txt does not
    give it (0 x 0 from readKittiCalibration, and where a raw file lacks S_rect_02); loadKittiFrame and loadKittiRawFrame
    take it from the images. */
    CV_PROP_RW Size imageSize;
};

/** @brief A rectified stereo frame with its LiDAR scan projected to a sparse disparity map.
 */
struct CV_EXPORTS_W_SIMPLE StereoLidarFrame
{
    CV_WRAP StereoLidarFrame() {}
    CV_PROP_RW String name;          //!< the frame's id or file stem
    CV_PROP_RW Mat left;             //!< left image, one grey channel (colour converted with cv::cvtColor)
    CV_PROP_RW Mat right;            //!< right image, likewise
    CV_PROP_RW Mat leftImage;        //!< left image as stored (colour where it is), for coloured outputs
    CV_PROP_RW Mat sparse;           //!< CV_32FC1 disparities of the projected scan in pixels, 0 = none
    CV_PROP_RW Mat groundTruth;      //!< CV_32FC1 disparities in pixels, -1 = none; empty where the data has none
    CV_PROP_RW KittiCalibration calibration;   //!< the calibration the scan was projected with
};

/** @brief Reads a KITTI calibration file of the object / stereo benchmarks (P2, P3, R0_rect and Tr_velo_to_cam in one
file, `calib.txt` of a KITTI 2015 folder).

Raises cv::Exception naming the file and the key when the file cannot be opened, a key is missing or has the wrong
number of values.
 */
CV_EXPORTS_W KittiCalibration readKittiCalibration(const String& path);

/** @brief Reads the calibration of a KITTI raw drive from its two files: calib_cam_to_cam.txt (P_rect_02, P_rect_03,
R_rect_00) and calib_velo_to_cam.txt (R, T). Errors as readKittiCalibration.
 */
CV_EXPORTS_W KittiCalibration readKittiRawCalibration(const String& camToCamPath, const String& veloToCamPath);

/** @brief The calibration of a KITTI raw drive (DRIVE = <date>/<date>_drive_<n>_sync): the two files in the drive
folder's parent, <date>/calib_cam_to_cam.txt and <date>/calib_velo_to_cam.txt.
 */
CV_EXPORTS_W KittiCalibration readKittiRawDriveCalibration(const String& drive);

/** @brief Reads a raw Velodyne scan (float32 x, y, z, reflectance per point, KITTI's `.bin`).
@return N x 4 CV_32FC1. Raises cv::Exception when the file cannot be read or is not a whole number of points.
 */
CV_EXPORTS_W Mat readVelodyneScan(const String& path);

/** @brief Reads a LiDAR point cloud, by the file's extension: PCD (`.pcd`, PCL's format: DATA ascii, binary or
binary_compressed; fields in any order, padding fields, any SIZE / TYPE / COUNT PCL writes, organised or not), PLY
(`.ply`: ascii, binary little or big endian; the vertex element's x, y, z and an optional intensity, other elements
skipped) or KITTI's `.bin` (readVelodyneScan).
@return N x 4 CV_32FC1: x, y, z and the intensity (0 where the file has none), in the file's order; points with a
NaN or infinite coordinate (an organised cloud's empty pixels) are dropped. Raises cv::Exception naming the file and
what is wrong: truncated data, no x, y or z, an unknown DATA kind or format, sizes that disagree with the header, a
corrupt compressed stream.
 */
CV_EXPORTS_W Mat readPointCloud(const String& path);

/** @brief Reads a KITTI disparity PNG (uint16, disparity x 256, 0 = none) as CV_32FC1 pixels with -1 for none.
 */
CV_EXPORTS_W Mat readKittiDisparity(const String& path);

/** @brief Reads a KITTI depth PNG (uint16, metres x 256, 0 = none) as disparity focalBaseline / depth, CV_32FC1 pixels
with -1 for none.
 */
CV_EXPORTS_W Mat readKittiDepthAsDisparity(const String& path, double focalBaseline);

/** @brief The frame ids of a KITTI-layout folder: DIR/frames.txt, whitespace-separated.
 */
CV_EXPORTS_W std::vector<String> readKittiFrameIds(const String& dir);

/** @brief Frame `id` of a KITTI-layout folder: image_2/ID_10.png, image_3/ID_10.png, velodyne/ID.bin and calib.txt,
and disp_occ_0/ID_10.png as ground truth where it exists.

The scan (every lidarEvery-th ring from ring firstRing, selectLidarRings) is projected with projectPointsToDisparity.
Raises cv::Exception naming the file that is missing or unreadable, or when the two images differ in size.
 */
CV_EXPORTS_W StereoLidarFrame loadKittiFrame(const String& dir, const String& id, int lidarEvery = 1,
                                             int firstRing = 0);

/** @overload The scan projected with the given calibration instead of calib.txt (for example a refined one,
LidarCalibration).
 */
CV_EXPORTS_AS(loadKittiFrameWithCalibration) StereoLidarFrame
loadKittiFrame(const String& dir, const String& id, const KittiCalibration& calibration, int lidarEvery = 1,
               int firstRing = 0);

/** @brief The frame names of a KITTI raw drive: the stems of image_02/data/<name>.png, sorted. Raises cv::Exception
when the folder holds none.
 */
CV_EXPORTS_W std::vector<String> readKittiRawFrameNames(const String& drive);

/** @brief Frame `name` of a KITTI raw drive (image_02/data, image_03/data, velodyne_points/data) with the drive's
calibration (readKittiRawDriveCalibration); raw drives have no ground truth. Errors as loadKittiFrame.
 */
CV_EXPORTS_W StereoLidarFrame loadKittiRawFrame(const String& drive, const String& name,
                                                const KittiCalibration& calibration, int lidarEvery = 1,
                                                int firstRing = 0);

/** @brief A Middlebury scene folder in one of the layouts 2003 (im2/im6, disp2 / 4), 2005-06 half size (view1/view5,
disp1 / 2), 2014 (im0/im1, disp0.pfm) or 2006 full size (aloeL/aloeR, aloeGT).
@param dir the scene's folder.
@param left output, the left image in one grey channel.
@param right output, likewise.
@param groundTruth output, CV_32FC1 pixels, -1 = unknown.
Raises cv::Exception when no layout matches or a file cannot be read.
 */
CV_EXPORTS_W void loadMiddleburyScene(const String& dir, OutputArray left, OutputArray right, OutputArray groundTruth);

/** @brief The paper's indoor protocol: each ground-truth pixel (> 0) is kept with probability `fraction`, drawn by
cv::RNG(seed) in row order.
@return CV_32FC1, the kept disparities, 0 = none.
 */
CV_EXPORTS_W Mat sampleGroundTruth(InputArray groundTruth, double fraction, int64 seed);

/** @brief A disparity map in KITTI's PNG encoding: uint16 round(d x 256); 0 = none (so d <= 0 is none, and a positive
disparity below 1/512 is stored as 1).
@param disparity CV_32FC1 pixels, negative = none.
 */
CV_EXPORTS_W Mat encodeKittiDisparity(InputArray disparity);

/** @brief Depth in the KITTI depth-completion encoding: uint16 round(metres x 256), 0 = none. A depth that does not
fit (beyond 256 m) is written as none rather than clamped to a wrong value.
@param depth CV_32FC1 metres (disparityToDepth), 0 = none.
 */
CV_EXPORTS_W Mat encodeKittiDepth(InputArray depth);

/** @brief Writes a disparity map as PFM, invalid pixels as +inf (Middlebury's "unknown"). Raises cv::Exception when
the file cannot be written.
@param disparity CV_32FC1 pixels, negative = none.
 */
CV_EXPORTS_W void writePfm(const String& path, InputArray disparity);

/** @brief Writes a point cloud as binary little-endian PLY: one vertex (float x, y, z; uchar red, green, blue) per
pixel whose point is finite, in row order. Raises cv::Exception when the file cannot be written.
@param points CV_32FC3 (disparityToPoints).
@param colors the image of the same size: grey or BGR(A), 8 or 16 bits.
 */
CV_EXPORTS_W void writePly(const String& path, InputArray points, InputArray colors);

//! @}

}} // namespace cv::lidarsgm

#endif
