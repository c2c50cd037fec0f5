#pragma once
// OpenGL 3.3 core for our own rendering (3D viewport, preview textures, screenshots): the system header
// with prototypes, since Mesa's libGL exports every 3.3 entry point. ImGui's backend uses its own loader
// in its own translation unit; the two never meet in one file.
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
