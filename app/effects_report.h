// `wsd check --effects`: the effects a scene uses (reflection, refraction, textures, soft
// shadows, ...) and, for each, the objects that call for it.
#pragma once

#include <ostream>

#include "lang/load.h"

namespace wsd::app {

void print_effects(const lang::LoadedScene& scene, const lang::SourceManager& sources, std::ostream& out);

}  // namespace wsd::app
