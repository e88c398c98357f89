#pragma once
// A self-contained HTML page of headings, paragraphs, tables and PNG images (paths relative to
// the page), for reports a person opens in a browser.
#include <string>
#include <vector>

namespace skelgrasp::presentation {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text);
  // Markup inserted as it is (e.g. SceneView3d::html); the caller escapes any text in it.
  void rawHtml(const std::string& html);
  // `file` relative to the page's directory.
  void image(const std::string& file, const std::string& caption, int width_px = 0);
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows);
  // Written atomically; throws IoError.
  void write(const std::string& path) const;
  std::string html() const;

  // Files the page references, in order (for checks).
  const std::vector<std::string>& images() const { return images_; }

 private:
  std::string title_;
  std::string body_;
  std::vector<std::string> images_;
};

// HTML-escapes &, <, >, ", '.
std::string escapeHtml(const std::string& text);

}  // namespace skelgrasp::presentation
