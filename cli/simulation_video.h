// flexure simulate's video (internal to cli/): the frame images as an MP4, encoded by ffmpeg.
#pragma once

#include <string>
#include <vector>

namespace flexure::cli {

// Whether ffmpeg can be run (it is looked up on PATH, as a shell would).
bool ffmpegAvailable();

// The frame images as an H.264 MP4 at `fps` frames per second, encoded by ffmpeg in a private
// temporary folder (single-threaded, bit-exact flags and no metadata: the same frames give the
// same bytes) and staged to `video` like every other output. InputError with ffmpeg's own message
// when it fails.
void writeVideo(const std::string& video, const std::vector<std::string>& pngs, double fps);

}  // namespace flexure::cli
