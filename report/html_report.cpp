#include "report/html_report.h"

#include <cmath>
#include <cstdio>

#include "core/file_io.h"

namespace hw::report {

std::string htmlEscape(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string fmt(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  const std::string l = std::to_string(level < 1 ? 1 : level > 4 ? 4 : level);
  body_ += "<h" + l + ">" + htmlEscape(text) + "</h" + l + ">\n";
}

void HtmlReport::paragraph(const std::string& text) { body_ += "<p>" + htmlEscape(text) + "</p>\n"; }

void HtmlReport::preformatted(const std::string& text) {
  body_ += "<pre>" + htmlEscape(text) + "</pre>\n";
}

void HtmlReport::images(const std::vector<std::string>& src,
                        const std::vector<std::string>& captions, int maxWidthPx) {
  body_ += "<div class=\"row\">\n";
  for (std::size_t i = 0; i < src.size(); ++i) {
    body_ += "<figure><a href=\"" + htmlEscape(src[i]) + "\"><img src=\"" + htmlEscape(src[i]) +
             "\"" + (maxWidthPx > 0 ? " style=\"max-width:" + std::to_string(maxWidthPx) + "px\"" : "") +
             "></a>";
    if (i < captions.size()) body_ += "<figcaption>" + htmlEscape(captions[i]) + "</figcaption>";
    body_ += "</figure>\n";
  }
  body_ += "</div>\n";
}

void HtmlReport::table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + htmlEscape(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (const auto& c : r) body_ += "<td>" + htmlEscape(c) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

std::string HtmlReport::html() const {
  return "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + htmlEscape(title_) +
         "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:1600px;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;"
         "text-align:right}th{background:#eee}img{max-width:100%;border:1px solid #ccc}"
         ".row{display:flex;flex-wrap:wrap;gap:12px}figure{margin:0}figcaption{font-size:90%;"
         "color:#555}pre{background:#f6f6f6;padding:8px}</style></head>\n<body>\n<h1>" +
         htmlEscape(title_) + "</h1>\n" + body_ + "</body></html>\n";
}

Status HtmlReport::write(const std::string& path) const { return writeFileAtomic(path, html()); }

}  // namespace hw::report
