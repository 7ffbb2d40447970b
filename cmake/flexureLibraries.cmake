# The library layers as targets, the same inside this build and in the installed package:
# flexure_<layer> here, flexure::<layer> for both (an alias here, the exported name there).
#
# Headers are included as "<layer>/x.h" (say "modeling/mesh.h"): from the source root here, and
# from <prefix>/include/flexure once installed (cmake/flexurePackage.cmake), so code built against
# the package writes the same #includes as the project's own code, and the headers, which include
# each other that way, are installed as they are.
function(flexure_library_layer target layer)
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${FLEXURE_ROOT}>
                                              $<INSTALL_INTERFACE:include/flexure>)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${layer})
  add_library(flexure::${layer} ALIAS ${target})
endfunction()

# Debian's Ceres was built on ATLAS and names ATLAS's own libf77blas and libatlas in its link
# interface: linked into an executable they come first in the dynamic symbol lookup and take every
# BLAS call, CHOLMOD's supernodal factorization included, from the libblas.so.3 the system chose
# (OpenBLAS, scripts/install-deps). Drops them from Ceres::ceres; flexureConfig.cmake does the same
# for the package's users.
function(flexure_drop_atlas_from_ceres)
  get_target_property(ceres_links Ceres::ceres INTERFACE_LINK_LIBRARIES)
  list(FILTER ceres_links EXCLUDE REGEX "/lib(f77blas|atlas)\\.so$")
  set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${ceres_links}")
endfunction()
