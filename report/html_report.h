#pragma once
// A static HTML page (no server, no scripts) that reads top to bottom:
// headings, paragraphs, tables and images referenced by relative path.
#include <string>
#include <vector>

#include "core/result.h"

namespace hw::report {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);
  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text);  // escaped
  void preformatted(const std::string& text);
  // Images side by side in one row; `src` relative to the page.
  void images(const std::vector<std::string>& src, const std::vector<std::string>& captions = {},
              int maxWidthPx = 0);
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows);
  std::string html() const;
  Status write(const std::string& path) const;  // atomic

 private:
  std::string title_;
  std::string body_;
};

std::string htmlEscape(const std::string& s);
// Fixed-point number for tables ("-" for NaN).
std::string fmt(double v, int decimals = 2);

}  // namespace hw::report
