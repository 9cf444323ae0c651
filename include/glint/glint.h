// glint's public C++ API, all of it: load a scene (glint/scene.h), edit it
// with the loader's checks, prepare and render it, explain a pixel, read and
// write images (glint/render.h); render into files frame by frame, with
// cancel and resume (glint/frames.h). Everything else in the library is
// internal and may change between versions.
#pragma once

#include "glint/error.h"
#include "glint/frames.h"
#include "glint/render.h"
#include "glint/scene.h"
#include "glint/version.h"
