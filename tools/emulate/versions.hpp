// The two versions of a kernel's source that an emulated case compares (tools/emulate_kernel.sh's old.inc and
// new.inc), in namespaces oldv and newv of cuda_impl: included after what the case defines there for them.
namespace cv { namespace lidarsgm { namespace detail { namespace cuda_impl {
namespace oldv {
#include "old.inc"
}
namespace newv {
#include "new.inc"
}
}}}}
using namespace cv::lidarsgm::detail;
using namespace cv::lidarsgm::detail::cuda_impl;
