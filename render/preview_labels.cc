// The labelled PNG of a preview (render/preview.h LabelledDisplay), drawn
// with OpenCV's built-in Hershey font (no font files needed).
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "render/preview.h"

namespace clothfit {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kInk(40, 40, 40);      // BGR
const cv::Scalar kArrow(180, 119, 31);  // BGR of a blue
constexpr int kRowBaseline = 17;        // in the band: the row's title
constexpr int kPanelBaseline = 37;      // ... the panels' titles
constexpr int kArrowHalf = 9;           // pixels, warp arrow half length

// sRGB transfer curve of the exposed value, clamped to [0, 1].
double Display(double v, double exposure) {
  const double x = std::clamp(v * exposure, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

// The largest scale up to `scale` at which `text` (plus `reserve` pixels)
// fits in `width` pixels, not below 0.3 (then it is cut at the panel's
// edge).
double FittingScale(const std::string& text, double scale, int width,
                    int reserve) {
  for (; scale > 0.3; scale -= 0.02) {
    int base = 0;
    if (cv::getTextSize(text, kFont, scale, 1, &base).width + reserve <=
        width) {
      break;
    }
  }
  return std::max(scale, 0.3);
}

// A double-headed arrow centred on `c` along the warp: `warp_deg` from the
// cylinder's axis, which is vertical on screen, towards +x (the right).
void WarpArrow(cv::Mat* image, cv::Point2d c, double warp_deg) {
  const double a = warp_deg * 3.14159265358979323846 / 180.0;
  const cv::Point2d d(std::sin(a) * kArrowHalf, -std::cos(a) * kArrowHalf);
  const cv::Point p(cvRound(c.x + d.x), cvRound(c.y + d.y));
  const cv::Point q(cvRound(c.x - d.x), cvRound(c.y - d.y));
  cv::arrowedLine(*image, q, p, kArrow, 2, cv::LINE_AA, 0, 0.4);
  cv::arrowedLine(*image, p, q, kArrow, 2, cv::LINE_AA, 0, 0.4);
}

}  // namespace

DisplayImage LabelledDisplay(const PreviewImage& image, double exposure) {
  const int size = image.panel_size > 0 ? image.panel_size : image.height;
  const int rows = size > 0 ? image.height / size : 0;
  const int columns = size > 0 ? image.width / size : 0;
  cv::Mat out(image.height + rows * kLabelBand, image.width, CV_8UC3,
              cv::Scalar(255, 255, 255));
  for (int row = 0; row < rows; ++row) {
    const int band = row * (size + kLabelBand);
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const glm::dvec3& v = image.At(x, row * size + y);
        cv::Vec3b& px = out.at<cv::Vec3b>(band + kLabelBand + y, x);
        for (int c = 0; c < 3; ++c) {
          px[2 - c] = cv::saturate_cast<uchar>(
              std::lround(255.0 * Display(v[c], exposure)));
        }
      }
    }
    if (static_cast<size_t>(row) < image.row_titles.size()) {
      const std::string& title = image.row_titles[row];
      cv::putText(out, title, {6, band + kRowBaseline}, kFont,
                  FittingScale(title, 0.5, image.width, 12), kInk, 1,
                  cv::LINE_AA);
    }
    for (int column = 0; column < columns; ++column) {
      const size_t panel = static_cast<size_t>(row) * columns + column;
      if (panel >= image.panel_titles.size()) break;
      const double warp = panel < image.panel_warp_deg.size()
                              ? image.panel_warp_deg[panel]
                              : std::nan("");
      const int arrow = std::isfinite(warp) ? 4 * kArrowHalf : 0;
      const std::string& title = image.panel_titles[panel];
      const double scale = FittingScale(title, 0.45, size, 12 + arrow);
      // Drawn into the panel's column only: a long title is cut there.
      cv::Mat column_band =
          out(cv::Rect(column * size, band, size, kLabelBand));
      cv::putText(column_band, title, {6, kPanelBaseline}, kFont, scale, kInk,
                  1, cv::LINE_AA);
      if (arrow > 0) {
        int base = 0;
        const int end =
            6 + cv::getTextSize(title, kFont, scale, 1, &base).width;
        WarpArrow(
            &column_band,
            {std::min<double>(end + 2 * kArrowHalf, size - kArrowHalf - 3),
             kPanelBaseline - 5.0},
            warp);
      }
    }
  }
  DisplayImage display;
  display.width = out.cols;
  display.height = out.rows;
  display.rgb.reserve(size_t(out.cols) * out.rows * 3);
  for (int y = 0; y < out.rows; ++y) {
    for (int x = 0; x < out.cols; ++x) {
      const cv::Vec3b& px = out.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) display.rgb.push_back(px[2 - c] / 255.0f);
    }
  }
  return display;
}

}  // namespace clothfit
