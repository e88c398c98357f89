// Bar charts with OpenCV drawing (the evaluation's histograms).
#include <fmt/format.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <filesystem>

#include "png_file.h"
#include "skelgrasp/common/atomic_file.h"
#include "skelgrasp/common/error.h"
#include "skelgrasp/presentation/render.h"

namespace skelgrasp::presentation {

void saveBarChartPng(const std::string& path, const std::string& title,
                     const std::vector<std::string>& x_labels, const std::vector<BarSeries>& series,
                     const std::string& y_label, int width, int height) {
  if (x_labels.empty() || series.empty()) throw InvalidArgument("bar chart: no data");
  for (const auto& s : series) {
    if (s.values.size() != x_labels.size())
      throw InvalidArgument("bar chart: series length differs from labels");
  }
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int left = 70, right = 20, top = 50, bottom = 60;
  const int plot_w = width - left - right, plot_h = height - top - bottom;
  double max_value = 0;
  for (const auto& s : series)
    max_value = std::max(max_value, *std::max_element(s.values.begin(), s.values.end()));
  max_value = max_value > 0 ? max_value * 1.1 : 1.0;
  const cv::Scalar ink(40, 40, 40), grid(220, 220, 220);
  auto y_of = [&](double v) { return top + plot_h - static_cast<int>(plot_h * v / max_value); };
  for (int k = 0; k <= 5; ++k) {
    const double v = max_value * k / 5;
    cv::line(image, {left, y_of(v)}, {left + plot_w, y_of(v)}, grid, 1);
    cv::putText(image, fmt::format("{:.2f}", v), {5, y_of(v) + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                ink, 1, cv::LINE_AA);
  }
  const double group_w = static_cast<double>(plot_w) / x_labels.size();
  const double bar_w = 0.8 * group_w / series.size();
  for (std::size_t g = 0; g < x_labels.size(); ++g) {
    for (std::size_t k = 0; k < series.size(); ++k) {
      const int x0 = left + static_cast<int>(g * group_w + 0.1 * group_w + k * bar_w);
      const int x1 = static_cast<int>(x0 + bar_w) - 1;
      const auto& c = series[k].colour;
      cv::rectangle(image, {x0, y_of(series[k].values[g])}, {std::max(x0, x1), top + plot_h},
                    cv::Scalar(c[2], c[1], c[0]), cv::FILLED);
    }
    if (g % std::max<std::size_t>(1, x_labels.size() / 10) == 0 || g + 1 == x_labels.size()) {
      cv::putText(image, x_labels[g], {left + static_cast<int>(g * group_w), top + plot_h + 18},
                  cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    }
  }
  cv::line(image, {left, top + plot_h}, {left + plot_w, top + plot_h}, ink, 1);
  cv::line(image, {left, top}, {left, top + plot_h}, ink, 1);
  cv::putText(image, title, {left, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.6, ink, 1, cv::LINE_AA);
  cv::putText(image, y_label, {5, top - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const int x = left + plot_w - 200, y = top + 10 + 20 * static_cast<int>(k);
    const auto& c = series[k].colour;
    cv::rectangle(image, {x, y - 10}, {x + 14, y + 2}, cv::Scalar(c[2], c[1], c[0]), cv::FILLED);
    cv::putText(image, series[k].label, {x + 20, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink, 1,
                cv::LINE_AA);
  }
  internal::writeBgrPng(path, image.cols, image.rows, image.ptr<std::uint8_t>(0), image.step[0]);
}

}  // namespace skelgrasp::presentation
