#pragma once
// gapfe version; kept in step with project(VERSION) in CMakeLists.txt.
#define GAPFE_VERSION_MAJOR 0
#define GAPFE_VERSION_MINOR 1
#define GAPFE_VERSION_PATCH 0
#define GAPFE_VERSION_STRING "0.1.0"
