#pragma once
// Scene files: the JSON description of a scene (format in configs/scenes/README.md, parameter
// tables in scene_loader.cpp) read into a Scene, with every file it reads hashed.

#include "core/config/params.h"
#include "core/scene/scene.h"

#include <filesystem>
#include <string>

namespace gibench {

// Reads the scene file `file`; relative paths in it resolve against its folder. Scene::files
// starts with `file` itself and Scene::description is its JSON. Throws InputError naming the
// file and JSON pointer of the first problem (unknown keys of an object are listed together).
Scene loadSceneFile(const std::filesystem::path& file);

// Reads a scene given inline as `block` (e.g. the scene object of a run config); relative paths
// resolve against block.baseDir(). Scene::files lists the files the scene reads but not the file
// holding `block`; Scene::description is block.json().
Scene loadScene(Params& block);

// The folder `${GIBENCH_SCENES}` stands for: the environment variable GIBENCH_SCENES when it is
// set and not empty, else <source dir>/../shared/scenes.
std::filesystem::path scenesDirectory();

// Reads string key `name` of `params` as a file path, lexically normalised: a leading
// `${GIBENCH_SCENES}` expands to scenesDirectory(), and a relative path resolves against
// params.baseDir(). Any other `${` is an InputError, so a misspelt variable is not read as a
// folder name.
std::filesystem::path readPath(Params& params, const std::string& name);

}  // namespace gibench
