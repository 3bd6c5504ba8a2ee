#include "viewer/app/report/report_html.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace uf::app {
namespace {

constexpr const char* kStyle =
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;line-height:1.45}"
    "h1,h2{border-bottom:1px solid #ddd;padding-bottom:.2em}"
    "table{border-collapse:collapse;margin:.8em 0}th,td{border:1px solid #ccc;padding:.25em .6em;"
    "text-align:left;vertical-align:top}th{background:#f3f3f3}"
    "pre{background:#f6f8fa;padding:.8em;overflow-x:auto;font-size:90%}code{background:#f6f8fa}"
    "img{max-width:100%;border:1px solid #eee;margin:.4em 0}.missing{color:#a00}";

std::string Escape(const std::string& text) {
  std::string out;
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
      default:
        out += c;
    }
  }
  return out;
}

// Escapes the text and turns `code` spans into <code>.
std::string Inline(const std::string& text) {
  std::string out;
  bool in_code = false;
  std::size_t start = 0;
  for (std::size_t at = text.find('`'); at != std::string::npos; at = text.find('`', start)) {
    out += Escape(text.substr(start, at - start)) + (in_code ? "</code>" : "<code>");
    in_code = !in_code;
    start = at + 1;
  }
  out += Escape(text.substr(start));
  if (in_code) out += "</code>";
  return out;
}

// "| a | b |" -> {"a", "b"}.
std::vector<std::string> Cells(const std::string& row) {
  std::vector<std::string> cells;
  std::string inner =
      row.substr(1, row.size() >= 2 && row.back() == '|' ? row.size() - 2 : std::string::npos);
  std::istringstream split(inner);
  for (std::string cell; std::getline(split, cell, '|');) {
    const std::size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  return cells;
}

std::string Image(const std::string& line, const std::filesystem::path& folder) {
  const std::size_t close = line.find("](");
  const std::string alt = line.substr(2, close - 2);
  const std::string file = line.substr(close + 2, line.size() - close - 3);
  std::ifstream in(folder / file, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  if (bytes.empty()) return "<p class=\"missing\">plot " + Escape(file) + " could not be read</p>\n";
  return "<figure><img alt=\"" + Escape(alt) + "\" src=\"data:image/png;base64," + Base64(bytes) +
         "\"><figcaption>" + Escape(file) + "</figcaption></figure>\n";
}

bool IsImageLine(const std::string& line) {
  return line.rfind("![", 0) == 0 && line.find("](") != std::string::npos && line.back() == ')';
}

}  // namespace

std::string Base64(std::span<const std::uint8_t> bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  // Each 3 bytes (24 bits) become 4 characters of 6 bits; a short last group is padded with '='.
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t group = std::uint32_t(bytes[i]) << 16;
    if (n > 1) group |= std::uint32_t(bytes[i + 1]) << 8;
    if (n > 2) group |= bytes[i + 2];
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(group >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::string MarkdownReportToHtml(const std::string& markdown, const std::filesystem::path& folder,
                                 const std::string& title) {
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                     Escape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n";
  std::istringstream lines(markdown);
  std::string line, paragraph;
  enum class Block { kNone, kList, kTable, kCode } block = Block::kNone;
  bool table_header = false;
  auto close = [&] {
    if (!paragraph.empty()) html += "<p>" + paragraph + "</p>\n";
    paragraph.clear();
    if (block == Block::kList) html += "</ul>\n";
    if (block == Block::kTable) html += "</table>\n";
    block = Block::kNone;
  };
  while (std::getline(lines, line)) {
    if (block == Block::kCode) {
      if (line.rfind("```", 0) == 0) {
        html += "</pre>\n";
        block = Block::kNone;
      } else {
        html += Escape(line) + "\n";
      }
      continue;
    }
    if (line.rfind("```", 0) == 0) {
      close();
      html += "<pre>";
      block = Block::kCode;
    } else if (line.rfind('#', 0) == 0) {
      close();
      const std::size_t level = std::min<std::size_t>(line.find_first_not_of('#'), 6);
      const std::string tag = std::to_string(level);
      html += "<h";
      html += tag;
      html += ">";
      html += Inline(line.substr(std::min(level + 1, line.size())));
      html += "</h";
      html += tag;
      html += ">\n";
    } else if (line.rfind("- ", 0) == 0) {
      if (block != Block::kList) {
        close();
        html += "<ul>\n";
        block = Block::kList;
      }
      html += "<li>" + Inline(line.substr(2)) + "</li>\n";
    } else if (line.rfind('|', 0) == 0) {
      if (block != Block::kTable) {
        close();
        html += "<table>\n";
        block = Block::kTable;
        table_header = true;
      }
      if (line.find("---") != std::string::npos && line.find_first_not_of("|-: ") == std::string::npos)
        continue;
      const std::string cell = table_header ? "th" : "td";
      html += "<tr>";
      for (const std::string& c : Cells(line)) html += "<" + cell + ">" + Inline(c) + "</" + cell + ">";
      html += "</tr>\n";
      table_header = false;
    } else if (IsImageLine(line)) {
      close();
      html += Image(line, folder);
    } else if (line.empty()) {
      close();
    } else {
      if (block != Block::kNone) close();
      if (!paragraph.empty()) paragraph += '\n';
      paragraph += Inline(line);
    }
  }
  if (block == Block::kCode) {  // an unclosed fence ends with the report
    html += "</pre>\n";
    block = Block::kNone;
  }
  close();
  return html + "</body>\n</html>\n";
}

}  // namespace uf::app
