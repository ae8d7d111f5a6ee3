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
        if (l.kind == LightKind::Point) {
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
        auto& users = set.shapes[size_t(e)];
        if (users.empty() || users.back() != uint32_t(shape)) users.push_back(uint32_t(shape));
    };
    // A shape's effects; an instance's are its members' (each with its own material, or the
    // instance's where it inherits), attributed to the instance.
    auto shape_effects = [&](const ShapeSpec& sh, uint32_t material, size_t i) {
        if (sh.kind == ShapeKind::Mesh && sh.mesh && !sh.mesh->normals.empty()) use(Effect::SmoothNormals, i);
        if (material >= spec.materials.size()) return;
        const MaterialSpec& m = spec.materials[material];
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
    };
    for (size_t i = 0; i < spec.shapes.size(); ++i) {
        const ShapeSpec& sh = spec.shapes[i];
        if (sh.kind != ShapeKind::Instance || sh.prototype >= spec.prototypes.size()) {
            shape_effects(sh, sh.material, i);
            continue;
        }
        for (const ShapeSpec& member : spec.prototypes[sh.prototype].shapes)
            shape_effects(member, member.material == kInheritMaterial ? sh.material : member.material, i);
    }
    return set;
}

}  // namespace wsd::render
