// flexure simulate's video: ffmpeg looked up on PATH, and the frame images encoded by it into a
// deterministic H.264 MP4 in a private temporary folder, staged like every other output.
#include "cli/simulation_video.h"

#include <stdlib.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "modeling/atomic_write.h"
#include "modeling/errors.h"

namespace flexure::cli {
namespace {

std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace

bool ffmpegAvailable() {
  return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

void writeVideo(const std::string& video, const std::vector<std::string>& pngs, double fps) {
  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / "flexure-video.XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr)
    throw InputError("--video " + video + ": cannot make a temporary folder for ffmpeg");
  const fs::path scratch(pattern);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  } cleanup{scratch};
  for (size_t k = 0; k < pngs.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05zu.png", k);
    std::ofstream((scratch / name).string(), std::ios::binary) << pngs[k];
  }
  char rate[32];
  std::snprintf(rate, sizeof rate, "%.17g", fps);
  const std::string command =
      "ffmpeg -nostdin -v error -y -framerate " + std::string(rate) + " -i '" +
      (scratch / "frame-%05d.png").string() +
      "' -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -threads 1 "
      "-map_metadata -1 -fflags +bitexact -flags:v +bitexact '" +
      (scratch / "video.mp4").string() + "' 2>'" + (scratch / "ffmpeg.log").string() + "'";
  const int status = std::system(command.c_str());
  if (status != 0 || !fs::exists(scratch / "video.mp4"))
    throw InputError("--video " + video + ": ffmpeg failed: " + readBytes(scratch / "ffmpeg.log"));
  modeling::writeFileAtomically(video, readBytes(scratch / "video.mp4"));
}

}  // namespace flexure::cli
