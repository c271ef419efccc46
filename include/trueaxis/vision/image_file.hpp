#pragma once
// Decodes an image file with OpenCV, turning OpenCV's exceptions (a header
// claiming more pixels than OpenCV decodes, a corrupt stream) into an
// InputError naming the file — never OpenCV's assertion text. Returns an
// empty Mat when OpenCV cannot read the file at all; callers say what they
// expected (grey PNG/JPEG, 16-bit thermal counts …).
#include <string>

#include <opencv2/core.hpp>

namespace trueaxis::vision {

cv::Mat DecodeImageFile(const std::string& path, int imread_flags);

}  // namespace trueaxis::vision
