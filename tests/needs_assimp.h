// Tests of PLY and glTF meshes need assimp, which a build may leave out
// (GLINT_ASSIMP): they are skipped there, saying so.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "glint/io/mesh_file.h"

#define GLINT_SKIP_WITHOUT_ASSIMP()                                                                      \
  if (const std::string glint_missing = glint::missing_mesh_support("mesh.ply"); !glint_missing.empty()) \
  GTEST_SKIP() << glint_missing
