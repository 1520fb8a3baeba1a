// tinyobj_impl.cpp — tinyobjloader compiled from its header for the fuzz
// build only, so that its parser is instrumented too (coverage feedback and
// AddressSanitizer); the default build links Debian's shared library.
// Debian builds that library with TINYOBJLOADER_USE_DOUBLE (the CMake block
// defines it here as well, as its imported target does for pmc_core).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
