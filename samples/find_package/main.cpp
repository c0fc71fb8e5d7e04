// Built against an installed OpenCV found with find_package(OpenCV REQUIRED lidarsgm): fuses a synthetic pair whose
// disparity is 9 everywhere and checks the answer, so the test proves the installed library works, not only links.
#include <opencv2/lidarsgm.hpp>
#include <opencv2/imgproc.hpp>
#include <cstdio>

int main()
{
    cv::Mat big(120, 200 + 9, CV_8UC1);
    cv::randu(big, 0, 256);
    cv::GaussianBlur(big, big, cv::Size(3, 3), 0);
    const cv::Mat left = big(cv::Rect(0, 0, 200, 120)), right = big(cv::Rect(9, 0, 200, 120));
    cv::Mat sparse(left.size(), CV_32FC1, cv::Scalar::all(0));
    for (int y = 5; y < 120; y += 10)
        for (int x = 5; x < 200; x += 10)
            sparse.at<float>(y, x) = 9.f;
    cv::Ptr<cv::lidarsgm::StereoLidarSGM> m = cv::lidarsgm::StereoLidarSGM::create(0, 32);
    cv::Mat disp;
    m->compute(left, right, sparse, disp);
    const int good = cv::countNonZero(cv::abs(disp(cv::Rect(20, 10, 170, 100)) - 9 * 16) <= 8);
    std::printf("lidarsgm from an installed OpenCV %s: %d of %d interior pixels at disparity 9\n", CV_VERSION, good,
                170 * 100);
    return good >= 170 * 100 * 99 / 100 ? 0 : 1;
}
