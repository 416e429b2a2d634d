// photoscene io: images (OpenImageIO), OBJ (tinyobjloader), the contract's JSON files
// (nlohmann-json), and whole-or-nothing file output.
#pragma once

#include "photoscene/io/files.hpp"
#include "photoscene/io/image_io.hpp"
#include "photoscene/io/json.hpp"
#include "photoscene/io/obj_io.hpp"
#include "photoscene/io/scene_json.hpp"
