// The viewer page's template and scripts, embedded in the library at build time
// (render/CMakeLists.txt generates viewer_assets.cpp), so that writing a page reads no file.
#pragma once

#include <string_view>

namespace flexure::render {

std::string_view viewerTemplate();       // render/viewer_page.html
std::string_view threeScript();          // three.js r111 (Debian libjs-three), minified
std::string_view orbitControlsScript();  // three.js r111's examples/js/controls/OrbitControls.js

}  // namespace flexure::render
