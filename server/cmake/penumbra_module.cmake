# penumbra_add_module(NAME SOURCES ... DEPENDS ... PRIVATE_DEPENDS ... LIBS ... PRIVATE_LIBS ...)
#
# One folder, one library target penumbra_<name> (alias penumbra::<name>), one include prefix
# <penumbra/<name>/...>. DEPENDS are Penumbra modules visible to users of this module;
# PRIVATE_DEPENDS are used by the implementation only, so their headers never leak upward.
function(penumbra_add_module name)
    cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS;LIBS;PRIVATE_LIBS" ${ARGN})
    set(target penumbra_${name})
    add_library(${target} STATIC ${ARG_SOURCES})
    add_library(penumbra::${name} ALIAS ${target})
    target_include_directories(${target} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
            PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
    foreach(dep IN LISTS ARG_DEPENDS)
        target_link_libraries(${target} PUBLIC penumbra::${dep})
    endforeach()
    foreach(dep IN LISTS ARG_PRIVATE_DEPENDS)
        target_link_libraries(${target} PRIVATE penumbra::${dep})
    endforeach()
    target_link_libraries(${target} PUBLIC ${ARG_LIBS} PRIVATE ${ARG_PRIVATE_LIBS} penumbra_warnings)
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
