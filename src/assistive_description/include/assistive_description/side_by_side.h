#pragma once
// Splitting a side-by-side frame into the two eyes, and the conversion to mono8.
#include <opencv2/core.hpp>
#include <string>

namespace assistive_description
{
/// Left = columns [0, W/2), right = [W/2, W) (swapped when swap_halves). The outputs are views
/// into `frame` (no copy). False with a message for an empty frame or an odd width.
bool splitSideBySide(const cv::Mat& frame, bool swap_halves, cv::Mat& left, cv::Mat& right,
                     std::string* error = nullptr);

/// 8-bit mono from 8-bit mono/BGR/BGRA (a copy, never a view). False for other types.
bool toMono8(const cv::Mat& in, cv::Mat& out, std::string* error = nullptr);

}  // namespace assistive_description
