// report.html: base64 against RFC 4648's test vectors, and a page made from report-style Markdown that
// carries its plots inline and refers to nothing outside itself.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"
#include "viewer/app/report/report_html.h"

namespace uf::app {
namespace {

std::string Encode(const std::string& text) {
  return Base64(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

TEST(ReportHtml, Base64MatchesRfc4648) {
  EXPECT_EQ(Encode(""), "");
  EXPECT_EQ(Encode("f"), "Zg==");
  EXPECT_EQ(Encode("fo"), "Zm8=");
  EXPECT_EQ(Encode("foo"), "Zm9v");
  EXPECT_EQ(Encode("foob"), "Zm9vYg==");
  EXPECT_EQ(Encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Encode("foobar"), "Zm9vYmFy");
  const std::vector<std::uint8_t> high = {0xff, 0xfe, 0xfd};  // all six-bit groups high: "//79"
  EXPECT_EQ(Base64(high), "//79");
}

TEST(ReportHtml, PageIsSelfContainedWithThePlotsInline) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir.path() / "plots");
  // Not a real PNG: the page must carry the file's bytes exactly, whatever they are.
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\x01\x02 plot bytes", 14);
  dir.Write("plots/ape.png", png);
  const std::string markdown =
      "# ultrafusion run\n\n**Run failed** in the map stage\n\n- dataset: `seq` (ultrafusion)\n- mode: lo\n\n"
      "## Stages\n\n| stage | status |\n|---|---|\n| odometry | ok |\n| map | failed |\n\n"
      "```\nstream   rate <Hz>\n```\n\n![plots/ape.png](plots/ape.png)\n![gone](plots/missing.png)\n";
  const std::string html = MarkdownReportToHtml(markdown, dir.path(), "ultrafusion run");

  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<style>"), std::string::npos);
  EXPECT_NE(html.find("<h1>ultrafusion run</h1>"), std::string::npos) << html;
  EXPECT_NE(html.find("<h2>Stages</h2>"), std::string::npos) << html;
  EXPECT_NE(html.find("<li>dataset: <code>seq</code> (ultrafusion)</li>"), std::string::npos) << html;
  EXPECT_NE(html.find("<tr><th>stage</th><th>status</th></tr>"), std::string::npos) << html;
  EXPECT_NE(html.find("<tr><td>map</td><td>failed</td></tr>"), std::string::npos) << html;
  EXPECT_EQ(html.find("---"), std::string::npos) << html;  // the separator row is not a table row
  EXPECT_NE(html.find("<pre>stream   rate &lt;Hz&gt;\n</pre>"), std::string::npos) << html;
  EXPECT_NE(html.find("src=\"data:image/png;base64," + Encode(png) + "\""), std::string::npos) << html;
  EXPECT_NE(html.find("plot plots/missing.png could not be read"), std::string::npos) << html;
  // Nothing fetched from elsewhere: no links, scripts or sources other than the inlined data.
  for (const char* external : {"http:", "https:", "<link", "<script", "src=\"plots", "url("})
    EXPECT_EQ(html.find(external), std::string::npos) << external;
}

}  // namespace
}  // namespace uf::app
