#include "skelgrasp/presentation/html_report.h"

#include <algorithm>

#include "skelgrasp/common/json.h"

namespace skelgrasp::presentation {

std::string escapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  const std::string tag = "h" + std::to_string(std::clamp(level, 1, 4));
  body_ += "<" + tag + ">" + escapeHtml(text) + "</" + tag + ">\n";
}

void HtmlReport::rawHtml(const std::string& html) {
  body_ += html;
}

void HtmlReport::paragraph(const std::string& text) {
  body_ += "<p>" + escapeHtml(text) + "</p>\n";
}

void HtmlReport::image(const std::string& file, const std::string& caption, int width_px) {
  images_.push_back(file);
  body_ += "<figure><img src=\"" + escapeHtml(file) + "\" alt=\"" + escapeHtml(caption) + "\"" +
           (width_px > 0 ? " width=\"" + std::to_string(width_px) + "\"" : std::string()) +
           "><figcaption>" + escapeHtml(caption) + "</figcaption></figure>\n";
}

void HtmlReport::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + escapeHtml(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const auto& cell : row) body_ += "<td>" + escapeHtml(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
         escapeHtml(title_) +
         "</title>\n<style>body{font-family:sans-serif;max-width:1500px;margin:1em auto;padding:0 "
         "1em}"
         "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:3px "
         "8px;"
         "text-align:left}th{background:#eee}figure{display:inline-block;margin:0.5em}"
         "img{border:1px solid "
         "#ccc}figcaption{font-size:90%;color:#444}</style>\n</head>\n<body>\n<h1>" +
         escapeHtml(title_) + "</h1>\n" + body_ + "</body>\n</html>\n";
}

void HtmlReport::write(const std::string& path) const {
  writeFileAtomically(path, html());
}

}  // namespace skelgrasp::presentation
