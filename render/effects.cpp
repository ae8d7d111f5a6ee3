// Effect analysis of a SceneSpec: a pass over lights, settings and each shape's material.
#include "render/effects.h"

namespace wsd::render {

const char* effect_name(Effect e) {
    switch (e) {
        case Effect::PointShadows:
            return "point-light shadows";
        case Effect::AreaShadows:
            return "area-light soft shadows";
        case Effect::Reflection:
            return "reflection";
        case Effect::Refraction:
            return "refraction";
        case Effect::Absorption:
            return "absorption";
        case Effect::ImageTextures:
            return "image textures";
        case Effect::ProceduralTextures:
            return "procedural textures";
        case Effect::Bumps:
            return "bumps";
        case Effect::SmoothNormals:
            return "smooth normals";
        case Effect::Specular:
            return "specular highlights";
        case Effect::Supersampling:
            return "supersampling";
        case Effect::AdaptiveSupersampling:
            return "adaptive supersampling";
        case Effect::AdaptiveLights:
            return "adaptive area lights";
    }
    return "?";
}

std::vector<std::string> EffectSet::names() const {
    std::vector<std::string> out;
    for (size_t i = 0; i < kEffectCount; ++i)
        if (has(Effect(i))) out.emplace_back(effect_name(Effect(i)));
    return out;
}

EffectSet analyse_effects(const SceneSpec& spec, bool force_adaptive_lights) {
    EffectSet set;
    for (const LightSpec& l : spec.lights) {
        if (l.kind != LightKind::Area) {  // a spot light's shadows are a point light's
            set.add(Effect::PointShadows);
        } else {
            set.add(Effect::AreaShadows);
            if ((l.adaptive || force_adaptive_lights) && l.samples_u * l.samples_v > 1)
                set.add(Effect::AdaptiveLights);
        }
    }
    if (spec.settings.supersamples > 1) {
        set.add(Effect::Supersampling);
        if (spec.settings.adaptive_supersampling) set.add(Effect::AdaptiveSupersampling);
    }
    auto use = [&set](Effect e, size_t shape) {
        set.add(e);
        set.shapes[size_t(e)].push_back(uint32_t(shape));
    };
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& sh = spec.shapes[i];
        if (sh.kind == ShapeKind::Mesh && sh.mesh && !sh.mesh->normals.empty()) use(Effect::SmoothNormals, i);
        if (sh.material >= spec.materials.size()) continue;
        const MaterialSpec& m = spec.materials[sh.material];
        if (m.reflection > 0) use(Effect::Reflection, i);
        if (m.transmission > 0) {
            use(Effect::Refraction, i);
            if (m.absorption != Color(0)) use(Effect::Absorption, i);
        }
        if (m.specular > 0) use(Effect::Specular, i);
        if (m.texture) {
            use(m.texture->kind == TextureKind::Image ? Effect::ImageTextures : Effect::ProceduralTextures,
                i);
        }
        if (m.bump && m.bump_strength > 0) use(Effect::Bumps, i);
    }
    return set;
}

}  // namespace wsd::render
