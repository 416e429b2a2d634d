// photoscene scene: mesh and material parts, cameras, views, lights, UV generation.
#pragma once

#include "photoscene/scene/camera.hpp"
#include "photoscene/scene/gltf_export.hpp"
#include "photoscene/scene/lights.hpp"
#include "photoscene/scene/material.hpp"
#include "photoscene/scene/mesh.hpp"
#include "photoscene/scene/scene.hpp"
