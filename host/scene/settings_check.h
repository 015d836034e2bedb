#pragma once
// Checking a value set in code (not read from a scene file) against its declaration in the
// settings registry (scene/settings.cpp): the typed views of the render layer validate with it,
// so each range and choice list is written once.
#include <string>

#include "scene/settings.h"

namespace nf::scene {

// Checks the value of setting `name` in r as a scene file's value is checked (the declaration's
// range or choices and its own check); throws nf::Error "where.name: message".
void check_setting(const RenderSettings& r, const std::string& name, const std::string& where);

}  // namespace nf::scene
