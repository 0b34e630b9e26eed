// The OpenGL 4.5 core API. libOpenGL.so.0 (glvnd) exports every core entry point, so the
// prototypes are used directly, without a loader. Private to lib/render.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
