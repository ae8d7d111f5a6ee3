// The renderer's input: a plain description of a scene, in world units, with no knowledge of the
// .wsd language. lang/lower.cpp fills it from evaluated values; tests build it by hand.
// Every list element may carry a `tag` (an opaque index chosen by the producer, e.g. into a table
// of source spans) so that errors found while building the scene can be reported at their source.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wsd::render {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Mat4 = glm::dmat4;
using Color = glm::dvec3;  // linear RGB

// ---- textures -------------------------------------------------------------------------------
enum class TextureKind { Image, Checker, Perlin };
enum class PerlinKind { Noise, Turbulence, Marble, Wood };

struct TextureSpec {
    TextureKind kind = TextureKind::Checker;
    std::string image_path;      // Image: path as it should be opened (already resolved)
    double checker_scale = 1.0;  // Checker: side of one square
    PerlinKind perlin = PerlinKind::Noise;
    Vec3 perlin_scale{1.0, 1.0, 1.0};  // Perlin: frequencies a, b, c
    int octaves = 9;                   // Perlin: L
    Color color1{1, 1, 1}, color2{0, 0, 0};
    uint32_t tag = 0;
};

// ---- materials ------------------------------------------------------------------------------
struct MaterialSpec {
    Color color{1, 1, 1};
    std::optional<TextureSpec> texture;
    std::optional<double> ambient;  // unset: settings.ambient
    double diffuse = 1.0;
    double specular = 0.0;
    double shininess = 50.0;
    double reflection = 0.0;
    double transmission = 0.0;
    double ior = 1.5;
    Color absorption{0, 0, 0};
    Color emission{0, 0, 0};          // radiance emitted from both sides
    std::optional<TextureSpec> bump;  // always a Perlin texture
    double bump_strength = 0.3;
    uint32_t tag = 0;
};

// ---- geometry -------------------------------------------------------------------------------
enum class ShapeKind { Sphere, Box, Triangle, Plane, Mesh, Cylinder, Cone, Torus, Disc, Csg, Instance };
enum class CsgOp { Union, Intersection, Difference };

// The word a scene writes for a shape kind ("sphere", "torus", "object" for an instance), for messages.
constexpr const char* shape_word(ShapeKind k) {
    switch (k) {
        case ShapeKind::Sphere:
            return "sphere";
        case ShapeKind::Box:
            return "box";
        case ShapeKind::Triangle:
            return "triangle";
        case ShapeKind::Plane:
            return "plane";
        case ShapeKind::Mesh:
            return "mesh";
        case ShapeKind::Cylinder:
            return "cylinder";
        case ShapeKind::Cone:
            return "cone";
        case ShapeKind::Torus:
            return "torus";
        case ShapeKind::Disc:
            return "disc";
        case ShapeKind::Csg:
            return "CSG";
        case ShapeKind::Instance:
            return "object";
    }
    return "shape";
}

// A shape inside a prototype or a CSG whose material is given by what contains it: the CSG's
// material, else the instance's (ShapeSpec::material of the Instance shape).
inline constexpr uint32_t kInheritMaterial = 0xffffffffu;

struct ShapeSpec;
// A CSG solid: its members in the CSG's own frame (each with its own object_to_world), combined by
// `op` (Difference: the first member minus all the others). Members are solids: sphere, box,
// closed cylinder or cone, torus, plane (the half-space n·p ≤ distance), closed mesh, nested CSG.
struct CsgSpec {
    CsgOp op = CsgOp::Union;
    std::vector<ShapeSpec> members;
};

// Geometry stored once and added any number of times by Instance shapes (a two-level BVH). Its
// shapes are in the prototype's own frame; none of them is an Instance.
struct PrototypeSpec {
    std::vector<ShapeSpec> shapes;
    uint32_t tag = 0;
};

// A triangle mesh in the object's own frame. uvs and normals are empty or one per vertex.
struct MeshData {
    std::vector<glm::vec3> vertices;
    std::vector<glm::uvec3> faces;
    std::vector<glm::vec2> uvs;
    std::vector<glm::vec3> normals;
    // For errors: where face i came from (e.g. an OBJ line number, or an element index); may be empty.
    std::vector<uint32_t> face_lines;
    std::string source_name;           // e.g. the OBJ file's path, for messages
    std::string face_origin = "line";  // what face_lines count in source_name: "line", "face element"
};

struct ShapeSpec {
    ShapeKind kind = ShapeKind::Sphere;
    // Sphere
    Vec3 center{0, 0, 0};
    double radius = 1.0;
    // Box
    Vec3 box_min{-1, -1, -1}, box_max{1, 1, 1};
    // Triangle: three vertices and optional per-vertex uvs
    Vec3 v[3]{};
    std::optional<std::array<Vec2, 3>> tri_uv;
    // Plane: n·p = distance in the object frame (normal is normalized by the builder)
    Vec3 normal{0, 1, 0};
    double distance = 0.0;
    double uv_scale = 1.0;
    // Mesh
    std::shared_ptr<const MeshData> mesh;
    // Cylinder (radius), cone (radius at base, cap_radius at cap): axis from base to cap; open:
    // no end caps. Disc: center, normal, radius, and a hole of radius `hole` (0: none).
    Vec3 base{0, 0, 0}, cap{0, 1, 0};
    double cap_radius = 0.0;
    bool open = false;
    double hole = 0.0;
    // Torus: centred at the origin of its frame, in the xz-plane, around the y axis.
    double major = 1.0, minor = 0.25;
    // Csg
    std::shared_ptr<const CsgSpec> csg;
    // Instance: an index into SceneSpec::prototypes, placed by object_to_world
    uint32_t prototype = 0;

    Mat4 object_to_world{1.0};  // scale/rotate/translate in the order written, composed
    uint32_t material = 0;      // index into SceneSpec::materials, or kInheritMaterial (see there)
    uint32_t tag = 0;
};

// ---- lights and camera ----------------------------------------------------------------------
enum class LightKind { Point, Area, Spot };
enum class LightSampling { Jittered, Uniform };

struct LightSpec {
    LightKind kind = LightKind::Point;
    Vec3 position{0, 0, 0};       // area: the centre of the parallelogram
    Vec3 u{0, 0, 0}, v{0, 0, 0};  // area: edge vectors
    int samples_u = 4, samples_v = 4;
    LightSampling sampling = LightSampling::Jittered;
    bool adaptive = false;
    Color color{1, 1, 1};
    double intensity = 1.0;
    // Spot: full intensity within `angle` degrees of the axis position → look_at, none beyond
    // `falloff`, smoothstep in between (0 < angle ≤ falloff ≤ 90).
    Vec3 look_at{0, -1, 0};
    double angle = 30.0, falloff = 45.0;
    uint32_t tag = 0;
};

struct CameraSpec {
    Vec3 position{0, 0, 0};
    Vec3 look_at{0, 0, 1};
    Vec3 up{0, 1, 0};
    double fov_degrees = 60.0;  // vertical
    uint32_t tag = 0;
};

struct Settings {
    int width = 640, height = 480;
    int supersamples = 1;
    bool adaptive_supersampling = false;
    bool exact_area_lights = false;  // closed-form diffuse term where a point sees a light whole
    double aa_threshold = 0.05;
    double bailout = 1.0 / 512.0;
    int max_depth = 8;
    double ambient = 0.2;
    Color background{0, 0, 0};
    uint32_t seed = 0;
    int indirect_samples = 0;  // Monte Carlo paths a camera sample's diffuse hits gather; 0: off
    int indirect_bounces = 3;  // the most diffuse reflections a path makes
    int caustic_photons = 0;   // 0: no caustics
};

struct SceneSpec {
    Settings settings;
    CameraSpec camera;
    std::vector<LightSpec> lights;
    std::vector<MaterialSpec> materials;
    std::vector<ShapeSpec> shapes;
    std::vector<PrototypeSpec> prototypes;
};

}  // namespace wsd::render

namespace wsd::render {

// An error found while building the renderer's scene from a SceneSpec (a value out of its field's
// range, a missing texture file, a degenerate triangle, parallel camera vectors...). `item` and
// `index` say which list element it concerns; `tag` is that element's tag; `field` is the name of
// the field it concerns as in the element's table (render/params.h; empty when it concerns the
// element as a whole); `face` is a mesh face index (or -1). The message is complete: it names the
// face it concerns, so a producer only chooses where to show it.
enum class SpecItem { Settings, Camera, Light, Material, Texture, Shape };
struct SpecError {
    SpecItem item = SpecItem::Shape;
    size_t index = 0;
    uint32_t tag = 0;
    std::string message;
    long face = -1;
    std::string_view field = {};
};

}  // namespace wsd::render
