// tinygltf as hlod uses it: header-only, with Draco (KHR_draco_mesh_compression primitives are
// decoded while loading), stb_image for embedded images, no image writer, external images left
// to the pipeline (loaded later by formats/image_io.h), nlohmann/json. Every translation unit that
// includes tiny_gltf.h includes this header instead, so that they all see the same classes;
// read_gltf.cpp defines TINYGLTF_IMPLEMENTATION before it.
#pragma once

#define TINYGLTF_ENABLE_DRACO
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_JSON
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>
