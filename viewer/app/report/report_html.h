// report.html beside report.md: the same report as one self-contained HTML page (a small inline style
// sheet, every plot inlined as a base64 PNG <img>, no external resource), so it can be mailed or opened
// anywhere. It is made from the Markdown itself, which keeps the two reports from drifting apart; only
// the subset of Markdown the reports use is understood: # headings, "- " lists, | tables |, ``` fenced
// blocks ```, ![alt](file.png) images on a line of their own, `code` spans and paragraphs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace uf::app {

// RFC 4648 base64 with '=' padding.
std::string Base64(std::span<const std::uint8_t> bytes);

// The page for `markdown`; images are read from paths relative to `folder` (one that cannot be read is
// shown as a note naming it). `title` goes into <title>.
std::string MarkdownReportToHtml(const std::string& markdown, const std::filesystem::path& folder,
                                 const std::string& title);

}  // namespace uf::app
