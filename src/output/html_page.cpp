// SPDX-License-Identifier: MIT
#include "src/output/html_page.h"

#include "src/base/error.h"
#include "src/output/report.h"


// The bundle's bytes, from the generated viewer_bundle.cpp (src/CMakeLists.txt).
extern "C" {
extern const char plancheck_viewer_bundle_begin[];
extern const char plancheck_viewer_bundle_end[];
extern const int plancheck_viewer_bundle_real;
}

namespace plancheck {

namespace {

constexpr std::string_view kDataOpen = "<script type=\"application/json\" id=\"plancheck-data\">";
constexpr std::string_view kScriptClose = "</script>";

// Inside <script>, the HTML parser ends the element at the first "</script"
// whatever the JavaScript around it: "</" becomes "<\/", the same string in
// JSON and in JavaScript string, template and regular expression literals.
void append_script_text(std::string& out, std::string_view text) {
  std::size_t from = 0;
  for (std::size_t at = text.find("</"); at != std::string_view::npos; at = text.find("</", from)) {
    out.append(text.substr(from, at - from)).append("<\\/");
    from = at + 2;
  }
  out.append(text.substr(from));
}

std::string html_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string_view viewer_bundle() {
  return {plancheck_viewer_bundle_begin,
          static_cast<std::size_t>(plancheck_viewer_bundle_end - plancheck_viewer_bundle_begin)};
}

bool viewer_bundle_is_real() { return plancheck_viewer_bundle_real != 0; }

std::string base64(const void* data, std::size_t bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (std::uint32_t{p[i + 1]} << 8) | p[i + 2];
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (i < bytes) {
    const bool two = i + 1 < bytes;
    const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (two ? std::uint32_t{p[i + 1]} << 8 : 0u);
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += two ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

void write_html_page(const std::filesystem::path& file, std::string_view title, std::string_view json) {
  const std::string_view bundle = viewer_bundle();
  std::string page;
  page.reserve(json.size() + bundle.size() + 1024);
  page += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  page.append("<title>").append(html_escape(title)).append("</title>\n</head>\n<body>\n");
  page.append(kDataOpen);
  append_script_text(page, json);
  page.append(kScriptClose).append("\n<script>");
  append_script_text(page, bundle);
  page.append(kScriptClose).append("\n</body>\n</html>\n");

  write_atomically(file, page);
}

std::string html_page_data(std::string_view page) {
  const std::size_t begin = page.find(kDataOpen);
  if (begin == std::string_view::npos) return {};
  const std::size_t from = begin + kDataOpen.size();
  const std::size_t end = page.find(kScriptClose, from);
  if (end == std::string_view::npos) return {};
  std::string out;
  const std::string_view text = page.substr(from, end - from);
  // Undo append_script_text: "<\/" back to "</" (JSON reads both the same).
  std::size_t at = 0;
  for (std::size_t k = text.find("<\\/"); k != std::string_view::npos; k = text.find("<\\/", at)) {
    out.append(text.substr(at, k - at)).append("</");
    at = k + 3;
  }
  out.append(text.substr(at));
  return out;
}

}  // namespace plancheck
