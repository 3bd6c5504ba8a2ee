#include "odometry/eval/plot_png.h"

#include <plplot.h>
#include <unistd.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "odometry/eval/plot_draw.h"
#include "odometry/eval/plot_style.h"

namespace uf::plot {
namespace {

// PLplot keeps global state (current stream, handlers): one plot at a time.
std::mutex plplot_mutex;
// While a plot renders: where a fatal PLplot error jumps to, and PLplot's last error message.
std::jmp_buf* fatal_jump = nullptr;
PLINT plplot_error_code = 0;
char plplot_message[4096];

void RememberMessage(const char* message) {
  std::snprintf(plplot_message, sizeof(plplot_message), "%s", message ? message : "");
}

// plexit() calls exit() once its handler returns, so during a render the handler jumps back instead.
int OnPlplotExit(const char* message) {
  RememberMessage(message);
  if (fatal_jump) std::longjmp(*fatal_jump, 1);
  return 1;
}

// plabort() reports a failed call and carries on; the message is kept (plsError keeps it off stderr).
void OnPlplotAbort(const char* message) { RememberMessage(message); }

bool PngDeviceAvailable() {
  constexpr int kMaxDevices = 256;
  const char* menu[kMaxDevices + 1];
  const char* names[kMaxDevices + 1];
  const char** menu_ptr = menu;
  const char** names_ptr = names;
  int count = kMaxDevices;
  plgDevs(&menu_ptr, &names_ptr, &count);
  for (int i = 0; i < count; ++i)
    if (names[i] && std::strcmp(names[i], "pngcairo") == 0) return true;
  return false;
}

// Sets up colours, page and axis style of a new stream, before and after plinit.
void InitStream(std::FILE* file) {
  plsdev("pngcairo");
  plsfile(file);
  plspage(0.0, 0.0, kWidthPx, kHeightPx, 0, 0);
  PLINT r[kColours.size()], g[kColours.size()], b[kColours.size()];
  for (std::size_t i = 0; i < kColours.size(); ++i)
    r[i] = kColours[i][0], g[i] = kColours[i][1], b[i] = kColours[i][2];
  plscmap0(r, g, b, static_cast<PLINT>(kColours.size()));
  plscol0a(kBand, kColours[kBand][0], kColours[kBand][1], kColours[kBand][2], kBandAlpha);
  plinit();
  PLFLT position[kTurbo.size()], red[kTurbo.size()], green[kTurbo.size()], blue[kTurbo.size()];
  for (std::size_t i = 0; i < kTurbo.size(); ++i)
    position[i] = kTurbo[i][0], red[i] = kTurbo[i][1], green[i] = kTurbo[i][2], blue[i] = kTurbo[i][3];
  plscmap1n(256);
  plscmap1l(1, static_cast<PLINT>(kTurbo.size()), position, red, green, blue, nullptr);
  plsxax(kAxisDigits, 0);
  plsyax(kAxisDigits, 0);
  SetTextScale(kTextScale);
  pladv(0);
}

// Opens a fresh PLplot stream writing a pngcairo PNG to `file`, draws the scene and ends the stream; the file
// is closed either way. Returns false if PLplot failed (plplot_message says why). PLplot's fatal errors leave
// through longjmp, so no object with a destructor may live between here and PLplot: the scene is prepared
// beforehand and only plain values are touched after setjmp.
bool RenderGuarded(std::FILE* file, DrawFunction draw, const void* scene) {
  std::jmp_buf jump;
  fatal_jump = &jump;
  plplot_error_code = 0;
  plplot_message[0] = '\0';
  plsexit(OnPlplotExit);
  plsabort(OnPlplotAbort);
  plsError(&plplot_error_code, plplot_message);  // stream 0, current until plmkstrm: errors off stderr
  volatile bool file_given = false, ok = false;
  if (setjmp(jump) == 0) {
    if (!PngDeviceAvailable()) {
      if (plplot_message[0] == '\0')  // else PLplot's own message (say, no driver folder) tells more
        RememberMessage("PLplot has no pngcairo device (Debian package plplot-driver-cairo)");
    } else {
      PLINT stream = 0;
      plmkstrm(&stream);
      plsError(&plplot_error_code, plplot_message);
      file_given = true;  // plend1 closes it once plinit ran
      InitStream(file);
      draw(scene);
      plend1();
      ok = plplot_error_code == 0;
    }
  } else if (setjmp(jump) == 0) {
    // PLplot gave up part way: take the file back if plinit never ran, then release the stream (a second
    // failure lands in the branch above's else and ends here too).
    PLINT level = 0;
    plglevel(&level);
    if (file_given && level == 0) {
      plsfile(nullptr);
      file_given = false;
    }
    plend1();
  }
  if (!file_given) std::fclose(file);
  fatal_jump = nullptr;
  return ok;
}

bool IsPngFile(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;
  unsigned char signature[8] = {};
  const bool ok =
      std::fread(signature, 1, 8, file) == 8 && std::memcmp(signature, "\x89PNG\r\n\x1a\n", 8) == 0;
  std::fclose(file);
  return ok;
}

}  // namespace

Status WritePng(const std::string& png_path, DrawFunction draw, const void* scene) {
  if (png_path.empty()) return Status::Error("plot: the PNG path is empty");
  const std::string tmp_path = png_path + ".tmp" + std::to_string(::getpid());
  std::FILE* file = std::fopen(tmp_path.c_str(), "wb");
  if (!file)
    return Status::Error("plot " + png_path + ": cannot write " + tmp_path + ": " + std::strerror(errno));
  bool rendered = false;
  std::string message;
  {
    std::lock_guard<std::mutex> lock(plplot_mutex);
    rendered = RenderGuarded(file, draw, scene);
    message = plplot_message;
  }
  // PLplot's messages come with newlines and ", aborting operation".
  message.erase(0, message.find_first_not_of(" \n"));
  message.erase(message.find_last_not_of(" \n") + 1);
  std::error_code ignored;
  if (!rendered || !IsPngFile(tmp_path)) {
    std::filesystem::remove(tmp_path, ignored);
    return Status::Error("plot " + png_path + ": PLplot did not write the PNG" +
                         (message.empty() ? std::string() : " (" + message + ")"));
  }
  std::error_code error;
  std::filesystem::rename(tmp_path, png_path, error);
  if (error) {
    std::filesystem::remove(tmp_path, ignored);
    return Status::Error("plot " + png_path + ": cannot rename " + tmp_path + ": " + error.message());
  }
  return Status();
}

}  // namespace uf::plot
