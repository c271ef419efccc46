#include "trueaxis/vision/image_file.hpp"

#include <opencv2/imgcodecs.hpp>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::vision {

cv::Mat DecodeImageFile(const std::string& path, int imread_flags) {
  try {
    return cv::imread(path, imread_flags);
  } catch (const cv::Exception& e) {
    // OpenCV refuses headers above CV_IO_MAX_IMAGE_PIXELS (2^30) by an assertion naming that limit.
    const bool too_big = std::string(e.err).find("CV_IO_MAX_IMAGE_PIXELS") != std::string::npos;
    throw InputError(path, 0, "image",
                     too_big ? "its header claims more than 2^30 pixels (a corrupt or hostile header; no real camera "
                               "frame is that large)"
                             : "the image data is corrupt and cannot be decoded");
  } catch (const std::bad_alloc&) {
    throw InputError(path, 0, "image", "the image is too large to decode in memory");
  }
}

}  // namespace trueaxis::vision
