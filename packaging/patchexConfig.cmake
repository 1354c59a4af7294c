# CMake package config of an installed patchex: find_package(patchex CONFIG REQUIRED), then
# target_link_libraries(your_engine PRIVATE patchex::patchex).
include(CMakeFindDependencyMacro)
find_dependency(Vulkan)  # patchex.h includes vulkan/vulkan.h

get_filename_component(_patchex_prefix "${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
if(NOT TARGET patchex::patchex)
  add_library(patchex::patchex SHARED IMPORTED)
  set_target_properties(patchex::patchex PROPERTIES
    IMPORTED_LOCATION "${_patchex_prefix}/lib/@SONAME@"
    IMPORTED_SONAME "@SONAME@"
    INTERFACE_INCLUDE_DIRECTORIES "${_patchex_prefix}/include"
    INTERFACE_LINK_LIBRARIES Vulkan::Vulkan)
endif()
unset(_patchex_prefix)
