// SPDX-License-Identifier: MIT
#include "src/output/html_page.h"

#include "src/base/error.h"
#include "src/base/text.h"



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
constexpr std::size_t kBufferBytes = 1 << 20;

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

HtmlPageWriter::HtmlPageWriter(const std::filesystem::path& file, std::string_view title) : file_(file) {
  buffer_.reserve(kBufferBytes);
  write("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
  write("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
  write("<title>");
  write(markup_escape(title));
  write("</title>\n</head>\n<body>\n");
  write(kDataOpen);
}

void HtmlPageWriter::data(std::string_view json) {
  std::size_t from = 0;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    std::string_view escape;
    if (c == '<') {
      escape = "\\u003c";
    } else if (c == '\xE2' && i + 2 < json.size() && json[i + 1] == '\x80' && (json[i + 2] == '\xA8' || json[i + 2] == '\xA9')) {
      escape = json[i + 2] == '\xA8' ? "\\u2028" : "\\u2029";
    } else {
      continue;
    }
    write(json.substr(from, i - from));
    write(escape);
    if (c != '<') i += 2;
    from = i + 1;
  }
  write(json.substr(from));
}

void HtmlPageWriter::finish() {
  write(kScriptClose);
  write("\n<script>");
  std::string bundle;
  append_script_text(bundle, viewer_bundle());
  write(bundle);
  write(kScriptClose);
  write("\n</body>\n</html>\n");
  flush();
  file_.commit();
}

void HtmlPageWriter::write(std::string_view bytes) {
  if (buffer_.size() + bytes.size() > kBufferBytes) flush();
  if (bytes.size() > kBufferBytes) {
    buffer_ = bytes;
    flush();
    return;
  }
  buffer_.append(bytes);
}

void HtmlPageWriter::flush() {
  file_.write(buffer_);
  buffer_.clear();
}

void write_html_page(const std::filesystem::path& file, std::string_view title, std::string_view json) {
  HtmlPageWriter page(file, title);
  page.data(json);
  page.finish();
}

std::string html_page_data(std::string_view page) {
  const std::size_t begin = page.find(kDataOpen);
  if (begin == std::string_view::npos) return {};
  const std::size_t from = begin + kDataOpen.size();
  const std::size_t end = page.find(kScriptClose, from);
  if (end == std::string_view::npos) return {};
  // \u003c and the like are JSON's own escapes: the text parses as it is.
  return std::string(page.substr(from, end - from));
}

}  // namespace plancheck
