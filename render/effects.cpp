// Effect analysis of a SceneSpec: a pass over lights, settings and each shape's material.
#include "render/effects.h"

#include "render/photon_trace.h"

namespace wsd::render {

namespace {

// Each member's own material (nested CSGs' members too) and smooth-normal meshes, on shape i.
template <class Material, class Use>
void csg_member_effects(const CsgSpec& csg, size_t i, const Material& material, const Use& use) {
    for (const ShapeSpec& m : csg.members) {
        if (m.kind == ShapeKind::Mesh && m.mesh && !m.mesh->normals.empty()) use(Effect::SmoothNormals, i);
        if (m.material != kInheritMaterial) material(m.material, i);
        if (m.kind == ShapeKind::Csg && m.csg) csg_member_effects(*m.csg, i, material, use);
    }
}

}  // namespace

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
        case Effect::Csg:
            return "CSG";
        case Effect::Emission:
            return "emitters";
        case Effect::IndirectLight:
            return "indirect light";
        case Effect::Caustics:
            return "caustics";
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
    if (spec.settings.indirect_samples > 0) set.add(Effect::IndirectLight);
    if (spec.settings.supersamples > 1) {
        set.add(Effect::Supersampling);
        if (spec.settings.adaptive_supersampling) set.add(Effect::AdaptiveSupersampling);
    }
    auto use = [&set](Effect e, size_t shape) {
        set.add(e);
        auto& list = set.shapes[size_t(e)];
        if (list.empty() || list.back() != uint32_t(shape)) list.push_back(uint32_t(shape));
    };
    // The effects of material `mat` on shape i (a CSG's members report through their solid).
    auto material = [&](uint32_t mat, size_t i) {
        if (mat >= spec.materials.size()) return;
        const MaterialSpec& m = spec.materials[mat];
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
        if (m.emission != Color(0)) use(Effect::Emission, i);
    };
    // A shape's effects with its material; an instance's are its members' (each with its own
    // material, or the instance's where it inherits), attributed to the instance.
    auto shape_effects = [&](const ShapeSpec& sh, uint32_t mat, size_t i) {
        if (sh.kind == ShapeKind::Mesh && sh.mesh && !sh.mesh->normals.empty()) use(Effect::SmoothNormals, i);
        if (sh.kind == ShapeKind::Csg && sh.csg) {
            use(Effect::Csg, i);
            csg_member_effects(*sh.csg, i, material, use);
        }
        material(mat, i);
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
    if (spec.settings.caustic_photons > 0) {
        // The objects that focus light (those the photons are aimed at).
        const CausticObjects objects = caustic_objects(spec);
        if (caustics_skipped(spec, objects).empty()) {
            set.add(Effect::Caustics);
            set.shapes[size_t(Effect::Caustics)] = objects.focusing;
        }
    }
    return set;
}

}  // namespace wsd::render
