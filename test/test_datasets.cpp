// This file is part of the lidarsgm module (an OpenCV extra module).
// The datasets API (opencv2/lidarsgm/datasets.hpp): the KITTI and KITTI raw readers on the shipped frames, Middlebury
// scenes, the LiDAR ring selection, the point cloud reader (PCD, PLY, KITTI .bin), the output encodings (KITTI
// disparity and depth PNGs, PFM, PLY), and the errors a user gets for a missing or malformed file.
#include "test_precomp.hpp"
#include "test_common.hpp"
#include "opencv2/core/utils/filesystem.hpp"
#include <fstream>
#include <set>

namespace opencv_test { namespace {

using namespace cv::lidarsgm;

//! A file in a fresh temporary folder, removed with it.
struct TempDir
{
    std::string path;
    TempDir() : path(cv::tempfile("")) { cv::utils::fs::createDirectories(path); }
    ~TempDir() { cv::utils::fs::remove_all(path); }
    std::string file(const std::string& name, const std::string& content) const
    {
        const std::string p = path + "/" + name;
        std::ofstream(p.c_str()) << content;
        return p;
    }
};

TEST(Lidarsgm_Datasets, kitti_calibration)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const KittiCalibration c = readKittiCalibration(dir + "/calib.txt");
    ASSERT_EQ(CV_64FC1, c.projection.type());
    ASSERT_EQ(Size(4, 3), c.projection.size());
    ASSERT_EQ(Size(4, 4), c.lidarToCamera.size());
    // f x baseline = P2[0,3] - P3[0,3] of the shipped file: 4.485728e+01 - (-3.395242e+02).
    EXPECT_NEAR(384.38148, c.focalBaseline, 1e-9);
    EXPECT_NEAR(721.5, c.projection.at<double>(0, 0), 1.0);
    // The transform is rigid: a rotation and a translation, last row 0 0 0 1.
    const Mat R = c.lidarToCamera(Rect(0, 0, 3, 3));
    EXPECT_LT(cvtest::norm(R * R.t(), Mat::eye(3, 3, CV_64F), NORM_INF), 1e-4);
    EXPECT_EQ(1.0, c.lidarToCamera.at<double>(3, 3));
    // The file's matrices as they are: P3, R0_rect and Tr_velo_to_cam, whose product is the transform.
    ASSERT_EQ(Size(4, 3), c.rightProjection.size());
    ASSERT_EQ(Size(3, 3), c.rectification.size());
    ASSERT_EQ(Size(4, 3), c.veloToCamera.size());
    EXPECT_NEAR(-3.395242e+02, c.rightProjection.at<double>(0, 3), 1e-3);
    Mat R0 = Mat::eye(4, 4, CV_64F), Tr = Mat::eye(4, 4, CV_64F);
    c.rectification.copyTo(R0(Rect(0, 0, 3, 3)));
    c.veloToCamera.copyTo(Tr(Rect(0, 0, 4, 3)));
    EXPECT_EQ(0, cvtest::norm(Mat(R0 * Tr), c.lidarToCamera, NORM_INF));
    EXPECT_EQ(Size(), c.imageSize);   // calib.txt has no size; loadKittiFrame takes the images'
    EXPECT_EQ(Size(1242, 375), loadKittiFrame(dir, "000002").calibration.imageSize);
}

TEST(Lidarsgm_Datasets, kitti_calibration_errors_name_the_file_and_key)
{
    TempDir tmp;
    try
    {
        readKittiCalibration(tmp.path + "/missing.txt");
        FAIL() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("missing.txt")) << e.err;
    }
    const std::string noP3 = tmp.file("calib.txt", "P2: 1 0 0 0 0 1 0 0 0 0 1 0\nR0_rect: 1 0 0 0 1 0 0 0 1\n"
                                                     "Tr_velo_to_cam: 1 0 0 0 0 1 0 0 0 0 1 0\n");
    try
    {
        readKittiCalibration(noP3);
        FAIL() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("no key P3")) << e.err;
    }
    const std::string shortP3 = tmp.file("short.txt", "P2: 1 0 0 0 0 1 0 0 0 0 1 0\nP3: 1 2 3\n");
    EXPECT_THROW(readKittiCalibration(shortP3), cv::Exception);
    EXPECT_THROW(readKittiRawDriveCalibration(tmp.path + "/drive_sync"), cv::Exception);
}

TEST(Lidarsgm_Datasets, kitti_frame)
{
    const std::string dir = cvtest::findDataDirectory("kitti");
    const std::vector<String> ids = readKittiFrameIds(dir);
    ASSERT_EQ(2u, ids.size());
    const StereoLidarFrame f = loadKittiFrame(dir, ids[0]);
    EXPECT_EQ(ids[0], f.name);
    ASSERT_EQ(CV_8UC1, f.left.type());
    EXPECT_EQ(f.left.size(), f.right.size());
    EXPECT_EQ(CV_8UC3, f.leftImage.type());
    ASSERT_EQ(CV_32FC1, f.sparse.type());
    ASSERT_EQ(CV_32FC1, f.groundTruth.type());
    EXPECT_EQ(f.left.size(), f.groundTruth.size());
    // A 64-line scan covers about 5-6 % of a KITTI image; every 4th ring (a 16-line LiDAR) about a quarter of that.
    const int n64 = countNonZero(f.sparse > 0);
    EXPECT_GT(n64, 15000);
    const int n16 = countNonZero(loadKittiFrame(dir, ids[0], 4).sparse > 0);
    EXPECT_NEAR(0.25, (double)n16 / n64, 0.05);
    // The same frame through the calibration overload: the same scan, bit for bit.
    const StereoLidarFrame g = loadKittiFrame(dir, ids[0], readKittiCalibration(dir + "/calib.txt"));
    EXPECT_EQ(0, cvtest::norm(f.sparse, g.sparse, NORM_INF));
    // A frame that is not there names its missing file.
    try
    {
        loadKittiFrame(dir, "999999");
        FAIL() << "no exception";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string::npos, e.err.find("999999")) << e.err;
    }
    EXPECT_THROW(readKittiFrameIds(dir + "/image_2"), cv::Exception);
    EXPECT_THROW(readKittiRawFrameNames(dir), cv::Exception);
    EXPECT_THROW(readVelodyneScan(dir + "/calib.txt"), cv::Exception);   // not whole 16-byte points
}

TEST(Lidarsgm_Datasets, middlebury_scene_and_sampling)
{
    Mat l, r, gt;
    ASSERT_NO_THROW(loadMiddleburyScene(cvtest::findDataDirectory("middlebury/cone"), l, r, gt));
    ASSERT_EQ(CV_8UC1, l.type());
    EXPECT_EQ(l.size(), r.size());
    ASSERT_EQ(CV_32FC1, gt.type());
    const int known = countNonZero(gt > 0);
    EXPECT_GT(known, gt.total() / 2);
    // 1 % of the known pixels, the same draw for the same seed.
    const Mat s = sampleGroundTruth(gt, 0.01, 1), s2 = sampleGroundTruth(gt, 0.01, 1);
    EXPECT_NEAR(0.01, (double)countNonZero(s > 0) / known, 0.002);
    EXPECT_EQ(0, cvtest::norm(s, s2, NORM_INF));
    Mat diff = (s > 0) & (s != gt);
    EXPECT_EQ(0, countNonZero(diff));
    TempDir tmp;
    EXPECT_THROW(loadMiddleburyScene(tmp.path, l, r, gt), cv::Exception);
}

TEST(Lidarsgm_Datasets, kitti_png_and_pfm)
{
    // KITTI PNG: round(d * 256), 0 = invalid (so d = 0 cannot be stored and becomes invalid).
    Mat png = encodeKittiDisparity(floatRow({ -1, 0, 2.3125f, 127.5f, 0.001f }));
    EXPECT_EQ(0, png.at<ushort>(0, 0));
    EXPECT_EQ(0, png.at<ushort>(0, 1));
    EXPECT_EQ(592, png.at<ushort>(0, 2));
    EXPECT_EQ(32640, png.at<ushort>(0, 3));
    EXPECT_EQ(1, png.at<ushort>(0, 4));  // a positive disparity stays valid

    // PFM: invalid written as +inf, Middlebury's "unknown".
    const std::string pfm = cv::tempfile(".pfm");
    ASSERT_NO_THROW(writePfm(pfm, Mat((Mat_<float>(2, 3) << -1, 0.5f, 37.0625f, 4, 5, 6))));
    Mat back = imread(pfm, IMREAD_UNCHANGED);
    ASSERT_EQ(CV_32FC1, back.type());
    expectSameFloats((Mat_<float>(2, 3) << std::numeric_limits<float>::infinity(), 0.5f, 37.0625f, 4, 5, 6), back);
    remove(pfm.c_str());
}

TEST(Lidarsgm_Datasets, kitti_depth_png_and_ply)
{
    // Depth PNG: metres x 256, 0 = none; a depth beyond 65535 / 256 m is none, not clamped.
    const Mat_<float> depth = (Mat_<float>(1, 4) << 0.f, 10.f, 255.99f, 300.f);
    const Mat png = encodeKittiDepth(depth);
    ASSERT_EQ(CV_16UC1, png.type());
    EXPECT_EQ(0, png.at<ushort>(0, 0));
    EXPECT_EQ(2560, png.at<ushort>(0, 1));
    EXPECT_EQ(65533, png.at<ushort>(0, 2));
    EXPECT_EQ(0, png.at<ushort>(0, 3));
    // PLY: a header naming the valid points, then x y z float32 and r g b per point, NaN pixels left out.
    Mat points(1, 3, CV_32FC3, Scalar::all(std::numeric_limits<float>::quiet_NaN()));
    points.at<Vec3f>(0, 1) = Vec3f(1.5f, -2.f, 7.25f);
    Mat bgr(1, 3, CV_8UC3, Scalar(10, 20, 30));
    const std::string path = cv::tempfile(".ply");
    ASSERT_NO_THROW(writePly(path, points, bgr));
    std::ifstream in(path.c_str(), std::ios::binary);
    std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    const size_t end = content.find("end_header\n");
    ASSERT_NE(std::string::npos, end);
    EXPECT_NE(std::string::npos, content.find("format binary_little_endian 1.0\n"));
    EXPECT_NE(std::string::npos, content.find("element vertex 1\n"));
    const std::string body = content.substr(end + 11);
    ASSERT_EQ(15u, body.size());
    float xyz[3];
    memcpy(xyz, body.data(), 12);   // the test hosts are little-endian
    EXPECT_EQ(1.5f, xyz[0]);
    EXPECT_EQ(-2.f, xyz[1]);
    EXPECT_EQ(7.25f, xyz[2]);
    EXPECT_EQ(30, (uchar)body[12]);   // red
    EXPECT_EQ(20, (uchar)body[13]);
    EXPECT_EQ(10, (uchar)body[14]);   // blue
}

TEST(Lidarsgm_Datasets, lidar_rings)
{
    // The shipped 64-line scans split into 64 rings; every 2nd / 4th ring keeps about a half / a quarter of the
    // points, all of them from the scan, and the top ring first.
    const std::string dir = cvtest::findDataDirectory("kitti");
    for (const char* id : { "000002", "000046" })
    {
        const Mat pts = readVelodyneScan(dir + "/velodyne/" + id + ".bin");
        EXPECT_EQ(64, countLidarRings(pts)) << id;
        const Mat all = selectLidarRings(pts, 1);
        EXPECT_EQ(pts.rows, all.rows);
        const Mat half = selectLidarRings(pts, 2), quarter = selectLidarRings(pts, 4);
        EXPECT_NEAR(0.5, (double)half.rows / pts.rows, 0.05) << id;
        EXPECT_NEAR(0.25, (double)quarter.rows / pts.rows, 0.05) << id;
        // The kept rings are whole rings of the scan, so the 16-line scan's points are all in the 32-line scan.
        std::set<std::vector<float> > in32;
        for (int i = 0; i < half.rows; i++)
            in32.insert(std::vector<float>(half.ptr<float>(i), half.ptr<float>(i) + 4));
        int missing = 0;
        for (int i = 0; i < quarter.rows; i++)
            missing += !in32.count(std::vector<float>(quarter.ptr<float>(i), quarter.ptr<float>(i) + 4));
        EXPECT_EQ(0, missing) << id;
        // The four ring offsets of the 16-line thinning split the scan: together they hold every point once.
        int total = 0;
        std::set<std::vector<float> > seen;
        for (int first = 0; first < 4; first++)
        {
            const Mat part = selectLidarRings(pts, 4, first);
            total += part.rows;
            for (int i = 0; i < part.rows; i++)
                seen.insert(std::vector<float>(part.ptr<float>(i), part.ptr<float>(i) + 4));
        }
        std::set<std::vector<float> > scan;
        for (int i = 0; i < pts.rows; i++)
            scan.insert(std::vector<float>(pts.ptr<float>(i), pts.ptr<float>(i) + 4));
        EXPECT_EQ(pts.rows, total) << id;
        EXPECT_TRUE(seen == scan) << id;
        // The top ring (highest elevation) is kept: the highest point of the scan's first ring is in every subset.
        double top = -1e9;
        for (int i = 0; i < quarter.rows; i++)
        {
            const float* p = quarter.ptr<float>(i);
            top = std::max(top, std::atan2((double)p[2], std::hypot((double)p[0], (double)p[1])));
        }
        EXPECT_GT(top * 180 / CV_PI, 1.5) << id;
    }
}


// ---- readPointCloud: PCD, PLY and KITTI .bin (PCL's and plyfile's own writers in the Python tests) ----------------

//! The error of readPointCloud(path), "" where it reads the file.
static std::string pointCloudError(const std::string& path)
{
    try
    {
        readPointCloud(path);
    }
    catch (const cv::Exception& e)
    {
        return e.err;
    }
    return std::string();
}

//! The bytes of a value as a string.
template <typename T> static std::string bytesOf(T v, bool bigEndian = false)
{
    std::string s((const char*)&v, sizeof(T));
    if (bigEndian)
        std::reverse(s.begin(), s.end());
    return s;
}

static void expectPoints(const Mat& m, const std::vector<Vec4f>& expected)
{
    ASSERT_EQ(CV_32FC1, m.type());
    ASSERT_EQ((int)expected.size(), m.rows);
    ASSERT_EQ(4, m.cols);
    for (int i = 0; i < m.rows; i++)
        for (int c = 0; c < 4; c++)
            EXPECT_EQ(expected[i][c], m.at<float>(i, c)) << "point " << i << ", column " << c;
}

TEST(Lidarsgm_Datasets, point_cloud_pcd)
{
    TempDir tmp;
    // ascii: fields in another order, a padding field of three values, an organised 2 x 2 cloud with one empty pixel.
    const std::string ascii = tmp.file("a.pcd",
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS intensity x _ y z\nSIZE 2 4 1 8 4\n"
        "TYPE U F I F F\nCOUNT 1 1 3 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n"
        "7 1.5 0 0 0 -2.25 3\n8 nan 0 0 0 nan nan\n9 4 1 2 3 5 6\n0 -1e3 0 0 0 0.5 1e-3\n");
    expectPoints(readPointCloud(ascii), { Vec4f(1.5f, -2.25f, 3.f, 7.f), Vec4f(4.f, 5.f, 6.f, 9.f),
                                          Vec4f(-1e3f, 0.5f, 1e-3f, 0.f) });
    // A field the reader does not map (a ring number where the intensity would be expected) is named, once.
    const std::string ring = tmp.file("ring.pcd", "VERSION 0.7\nFIELDS x y z ring_id\nSIZE 4 4 4 2\nTYPE F F F U\n"
                                      "COUNT 1 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3 17\n");
    {
        CapturedLog log;
        expectPoints(readPointCloud(ring), { Vec4f(1.f, 2.f, 3.f, 0.f) });
        readPointCloud(ring);
        const std::string said = log.str();
        EXPECT_NE(std::string::npos, said.find(ring + ": the field ring_id is not read")) << said;
        EXPECT_EQ(said.find("ring_id"), said.rfind("ring_id")) << "twice: " << said;
    }
    // binary: x double, y float, z int16, a 2-byte pad, no intensity.
    const std::string header = "VERSION 0.7\nFIELDS x y z _\nSIZE 8 4 2 2\nTYPE F F I U\nCOUNT 1 1 1 1\nWIDTH 2\n"
                               "HEIGHT 1\nPOINTS 2\nDATA binary\n";
    const std::string records = bytesOf(1.25) + bytesOf(2.5f) + bytesOf((short)-3) + bytesOf((ushort)0) +
                                bytesOf(-4.0) + bytesOf(0.125f) + bytesOf((short)7) + bytesOf((ushort)0);
    const std::string binary = tmp.file("b.pcd", header + records);
    expectPoints(readPointCloud(binary), { Vec4f(1.25f, 2.5f, -3.f, 0.f), Vec4f(-4.f, 0.125f, 7.f, 0.f) });
    EXPECT_NE(std::string::npos, pointCloudError(tmp.file("short.pcd", header + records.substr(0, 30)))
                                     .find("truncated")) << "binary data one record short";
    // binary_compressed: the fields one after the other (x x y y z z, all 1.0f), as LZF: a literal run of 4 bytes,
    // then a back-reference of 20 bytes 4 back.
    const std::string lzf = std::string("\x03\x00\x00\x80\x3f\xe0\x0b\x03", 8);
    const std::string compressed = tmp.file("c.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                                     "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary_compressed\n" +
                                                     bytesOf((unsigned)lzf.size()) + bytesOf(24u) + lzf);
    expectPoints(readPointCloud(compressed), { Vec4f(1.f, 1.f, 1.f, 0.f), Vec4f(1.f, 1.f, 1.f, 0.f) });
}

TEST(Lidarsgm_Datasets, point_cloud_ply_and_kitti_bin)
{
    TempDir tmp;
    // ascii, CRLF line ends, an extra property, faces after the vertices.
    const std::string ascii = tmp.file("a.ply",
        "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 3\r\nproperty float nx\r\n"
        "property double x\r\nproperty double y\r\nproperty double z\r\nproperty uchar intensity\r\n"
        "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
        "0 1 2 3 200\r\n0 inf 0 0 1\r\n0 -4 5.5 6 0\r\n3 0 1 2\r\n");
    expectPoints(readPointCloud(ascii), { Vec4f(1.f, 2.f, 3.f, 200.f), Vec4f(-4.f, 5.5f, 6.f, 0.f) });
    // binary big endian, a list before the vertices, float coordinates, no intensity.
    const std::string big = tmp.file("b.ply",
        "ply\nformat binary_big_endian 1.0\nelement camera 1\nproperty list uchar float k\nelement vertex 2\n"
        "property float x\nproperty float y\nproperty float z\nend_header\n" + bytesOf((unsigned char)2) +
        bytesOf(9.f, true) + bytesOf(8.f, true) + bytesOf(1.f, true) + bytesOf(2.f, true) + bytesOf(3.f, true) +
        bytesOf(-1.f, true) + bytesOf(-2.f, true) + bytesOf(-3.f, true));
    expectPoints(readPointCloud(big), { Vec4f(1.f, 2.f, 3.f, 0.f), Vec4f(-1.f, -2.f, -3.f, 0.f) });
    // KITTI's .bin: readVelodyneScan's rows (a real scan has no NaN).
    const std::string scan = cvtest::findDataFile("kitti/velodyne/000002.bin");
    const Mat a = readPointCloud(scan), b = readVelodyneScan(scan);
    ASSERT_EQ(b.size(), a.size());
    EXPECT_EQ(0, cvtest::norm(a, b, NORM_INF));
}

TEST(Lidarsgm_Datasets, point_cloud_errors_name_the_file_and_fault)
{
    TempDir tmp;
    const std::string xyz = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
    const struct
    {
        std::string name, content, message;
    } cases[] = {
        { "noz.pcd", "FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2\n", "FIELDS has no z" },
        { "kind.pcd", xyz + "WIDTH 1\nPOINTS 1\nDATA binary_lzma\n", "unknown DATA kind 'binary_lzma'" },
        { "points.pcd", xyz + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n", "POINTS 3 disagrees with WIDTH x HEIGHT" },
        { "sizes.pcd", "FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n",
          "SIZE, TYPE and COUNT give" },
        { "type.pcd", "FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n",
          "field z of type F has 2 bytes" },
        { "token.pcd", xyz + "WIDTH 2\nPOINTS 2\nDATA ascii\n1 2 3\n4 five 6\n", "'five' where a number belongs" },
        { "ends.pcd", xyz + "WIDTH 2\nPOINTS 2\nDATA ascii\n1 2 3\n4 5\n", "the data ends at point 1 of 2" },
        { "noheader.pcd", xyz + "WIDTH 1\n", "the header ends before its DATA line" },
        { "lzf.pcd", xyz + "WIDTH 1\nPOINTS 1\nDATA binary_compressed\n" + bytesOf(2u) + bytesOf(12u) + "\xe0\x01",
          "the compressed data is corrupt" },
        { "lzfsize.pcd", xyz + "WIDTH 1\nPOINTS 1\nDATA binary_compressed\n" + bytesOf(2u) + bytesOf(16u) +
                             std::string("\x00\x01", 2),
          "uncompressed size 16 disagrees with 1 points of 12 bytes" },
        { "lzfshort.pcd", xyz + "WIDTH 1\nPOINTS 1\nDATA binary_compressed\n" + bytesOf(9u) + bytesOf(12u) +
                              std::string("\x00\x01", 2),
          "truncated: 9 compressed bytes announced, 2 there" },
        { "notply.ply", "solid cube\n", "not a PLY file" },
        { "format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown format 'binary_middle_endian'" },
        { "nox.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\nend_header\n1 2\n",
          "the vertex element has no x" },
        { "short.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                       "property float z\nend_header\n" + bytesOf(1.f) + bytesOf(2.f) + bytesOf(3.f) + bytesOf(4.f),
          "truncated in element vertex 1 of 2" },
        { "cloud.xyz", "1 2 3\n", "unknown file type" },
    };
    for (const auto& c : cases)
    {
        const std::string err = pointCloudError(tmp.file(c.name, c.content));
        EXPECT_NE(std::string::npos, err.find(c.name)) << c.name << ": " << err;
        EXPECT_NE(std::string::npos, err.find(c.message)) << c.name << ": " << err;
    }
    EXPECT_NE(std::string::npos, pointCloudError(tmp.path + "/missing.pcd").find("cannot open point cloud"));
}

}} // namespace
