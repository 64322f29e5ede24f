# Checks the layering of the library (docs/design.md, "Layers"): a file in
# include/jade/<layer>/ or src/<layer>/ includes only headers of its own layer
# or of layers below it, and apps/ only the library. Run as
#   cmake -DROOT=<source dir> -P cmake/CheckLayers.cmake
# Prints every offending include and fails when there is one.

# Rank of each layer; volume and geometry are siblings and may not include
# each other.
set(rank_core 0)
set(rank_volume 1)
set(rank_geometry 1)
set(rank_io 2)
set(rank_render 3)
set(rank_fit 4)
set(rank_app 5)
set(layers core volume geometry io render fit app)

set(bad 0)
foreach(layer ${layers})
  file(GLOB_RECURSE files "${ROOT}/include/jade/${layer}/*.h" "${ROOT}/src/${layer}/*.cpp")
  foreach(f ${files})
    file(STRINGS "${f}" includes REGEX "^#include \"jade/")
    foreach(line ${includes})
      string(REGEX MATCH "jade/([a-z_]+)/" _ "${line}")
      set(target "${CMAKE_MATCH_1}")
      if(NOT DEFINED rank_${target})
        message("${f}: '${line}' names no layer")
        math(EXPR bad "${bad} + 1")
      elseif(NOT target STREQUAL layer AND NOT rank_${target} LESS rank_${layer})
        message("${f}: layer '${layer}' includes '${line}' from layer '${target}'")
        math(EXPR bad "${bad} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
if(bad GREATER 0)
  message(FATAL_ERROR "${bad} include(s) break the layering")
endif()
message("layering: every include points down")
