#pragma once
// Meshes built in code for tests (owned by the test-support work; see fixtures.cpp).
#include "maxslice/mesh/triangle_mesh.hpp"
