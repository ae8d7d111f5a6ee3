// Cylinders, cones, tori and discs: silhouette areas against their closed forms (an orthographic
// grid of parallel rays, one per cell, counted), surface points on the surface, UVs, and the hard
// cases of docs/robustness.md (the torus quartic for grazing and far rays and at every size, a
// cylinder seen along its axis and edge-on, a ray through a cone's apex).
#include <catch2/catch.hpp>
#include <cmath>

#include "render/quadric_prims.h"
#include "tests/render/geometry_test_util.h"

using namespace wsd::render;
using namespace wsd::render::test;

namespace {

ShapeSpec cylinder(Vec3 base, Vec3 cap, double r, bool open = false) {
    ShapeSpec s;
    s.kind = ShapeKind::Cylinder;
    s.base = base;
    s.cap = cap;
    s.radius = r;
    s.open = open;
    return s;
}

ShapeSpec cone(Vec3 base, double r0, Vec3 cap, double r1, bool open = false) {
    ShapeSpec s = cylinder(base, cap, r0, open);
    s.kind = ShapeKind::Cone;
    s.cap_radius = r1;
    return s;
}

ShapeSpec torus(double major, double minor, Mat4 m = Mat4(1.0)) {
    ShapeSpec s;
    s.kind = ShapeKind::Torus;
    s.major = major;
    s.minor = minor;
    s.object_to_world = m;
    return s;
}

ShapeSpec disc(Vec3 c, Vec3 n, double r, double hole) {
    ShapeSpec s;
    s.kind = ShapeKind::Disc;
    s.center = c;
    s.normal = n;
    s.radius = r;
    s.hole = hole;
    return s;
}

// Parallel rays along `dir` from far behind a square of side `side` centred at `centre`, normal
// to dir, one through the middle of each of n×n cells; origins `back` units behind the square.
struct Grid {
    Vec3 centre, dir, e1, e2;
    double side;
    int n;
    double back;
    Ray ray(int i, int j) const {
        const double a = ((i + 0.5) / n - 0.5) * side, b = ((j + 0.5) / n - 0.5) * side;
        return {centre + a * e1 + b * e2 - back * dir, dir};
    }
    double cell_area() const { return (side / n) * (side / n); }
};

Grid grid_along(Vec3 dir, Vec3 centre, double side, int n, double back) {
    dir = glm::normalize(dir);
    const Vec3 helper = std::abs(dir.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    // Turned about dir so that no straight edge of a silhouette runs along the cells (which
    // would count a whole row in or out at once).
    const Vec3 a = glm::normalize(glm::cross(helper, dir));
    const Vec3 b = glm::cross(dir, a);
    const double c = std::cos(0.3), s = std::sin(0.3);
    const Vec3 e1 = c * a + s * b, e2 = c * b - s * a;
    return {centre, dir, e1, e2, side, n, back};
}

// The silhouette area: hit cells × cell area.
double coverage(const Geometry& g, const Grid& grid) {
    RayStats st;
    long hits = 0;
    for (int j = 0; j < grid.n; ++j)
        for (int i = 0; i < grid.n; ++i)
            if (g.intersect(grid.ray(i, j), std::numeric_limits<double>::infinity(), st)) ++hits;
    return double(hits) * grid.cell_area();
}

std::unique_ptr<Geometry> one(const ShapeSpec& s) {
    return build_ok(scene_of({s}));
}

// The distance of p from the torus surface (major circle in the xz-plane).
double torus_distance(double major, double minor, Vec3 p) {
    const double rho = std::sqrt(p.x * p.x + p.z * p.z);
    return std::hypot(rho - major, p.y) - minor;
}

}  // namespace

TEST_CASE("cylinder silhouette areas match 2rh·sin φ + πr²·|cos φ|", "[quadric][analytic]") {
    const double r = 0.7, h = 2.0;
    auto g = one(cylinder({0, -1, 0}, {0, 1, 0}, r));
    for (double deg : {0.0, 30.0, 60.0, 90.0}) {
        const double phi = deg * kPi / 180;
        const Vec3 dir(std::sin(phi), -std::cos(phi), 0);  // φ from the axis
        const double expected = 2 * r * h * std::sin(phi) + kPi * r * r * std::abs(std::cos(phi));
        const double area = coverage(*g, grid_along(dir, {0, 0, 0}, 3.3, 397, 50));
        INFO("view at " << deg << " degrees from the axis");
        CHECK(area == Approx(expected).epsilon(4e-3));
    }
}

TEST_CASE("cone silhouette areas: a trapezoid from the side, a disc along the axis", "[quadric][analytic]") {
    const double r0 = 1.0, r1 = 0.25, h = 2.0;
    for (double top : {r1, 0.0}) {
        auto g = one(cone({0, -1, 0}, r0, {0, 1, 0}, top));
        INFO("cap radius " << top);
        CHECK(coverage(*g, grid_along({0, 0, 1}, {0, 0, 0}, 2.5, 397, 50)) ==
              Approx((r0 + top) * h).epsilon(4e-3));
        CHECK(coverage(*g, grid_along({0, -1, 0}, {0, 0, 0}, 2.5, 397, 50)) ==
              Approx(kPi * r0 * r0).epsilon(4e-3));
    }
}

TEST_CASE("torus silhouette areas: an annulus along the axis, a stadium edge-on", "[quadric][analytic]") {
    for (auto [major, minor] : {std::pair{1.0, 0.3}, std::pair{0.5, 0.8}}) {
        auto g = one(torus(major, minor));
        const double reach = major + minor;
        const double along = minor < major ? 4 * kPi * major * minor : kPi * reach * reach;
        const double edge_on = 4 * major * minor + kPi * minor * minor;
        INFO("major " << major << ", minor " << minor);
        CHECK(coverage(*g, grid_along({0, -1, 0}, {0, 0, 0}, 2.3 * reach, 397, 50)) ==
              Approx(along).epsilon(4e-3));
        CHECK(coverage(*g, grid_along({0, 0, 1}, {0, 0, 0}, 2.3 * reach, 397, 50)) ==
              Approx(edge_on).epsilon(4e-3));
    }
}

TEST_CASE("disc with a hole covers π(r² − hole²)", "[quadric][analytic]") {
    auto g = one(disc({0.5, 0.25, 0}, {1, 2, 0.5}, 1.0, 0.4));
    const Vec3 n = glm::normalize(Vec3(1, 2, 0.5));
    CHECK(coverage(*g, grid_along(n, {0.5, 0.25, 0}, 2.2, 400, 50)) ==
          Approx(kPi * (1 - 0.16)).epsilon(4e-3));
    // Seen exactly edge-on, a disc has no area.
    const Grid edge = grid_along(glm::normalize(glm::cross(n, Vec3(0, 0, 1))), {0.5, 0.25, 0}, 2.2, 60, 50);
    CHECK(coverage(*g, edge) == 0);
}

TEST_CASE("hit points lie on the surface, with outward normals and UVs in [0, 1]", "[quadric]") {
    Rng rng(7);
    const std::vector<ShapeSpec> shapes = {cylinder({0.2, -1, 0.1}, {0.5, 1, -0.3}, 0.6),
                                           cone({0, -1, 0}, 0.8, {0.3, 1, 0.2}, 0.2), torus(1, 0.35),
                                           torus(0.4, 0.9), disc({0, 0, 0}, {0.3, 1, 0.2}, 1, 0.3)};
    for (size_t k = 0; k < shapes.size(); ++k) {
        auto g = one(shapes[k]);
        RayStats st;
        int hits = 0;
        for (int i = 0; i < ray_budget(4000); ++i) {
            const Vec3 o = 4.0 * rng.unit_vector();
            const Vec3 target = rng.in_box(Vec3(-1), Vec3(1));
            const Ray ray{o, target - o};
            auto hit = g->intersect(ray, std::numeric_limits<double>::infinity(), st);
            if (!hit) continue;
            ++hits;
            const SurfaceHit s = g->surface(ray, *hit);
            INFO("shape " << k << " ray " << i);
            REQUIRE(is_finite(s.p));
            CHECK(glm::length(s.ng) == Approx(1).epsilon(1e-12));
            CHECK(s.uv.x >= 0);
            CHECK(s.uv.x < 1);
            CHECK(s.uv.y >= 0);
            CHECK(s.uv.y <= 1);
            // Outward: a step along the normal leaves the solid (the torus: away from its tube).
            if (shapes[k].kind == ShapeKind::Torus) {
                CHECK(std::abs(torus_distance(shapes[k].major, shapes[k].minor, s.p)) < 1e-12);
                CHECK(torus_distance(shapes[k].major, shapes[k].minor, s.p + 1e-6 * s.ng) > 0);
            }
            CHECK(glm::length(s.p - (ray.o + hit->t * ray.d)) < 1e-9);
        }
        CHECK(hits > ray_budget(400));
    }
}

TEST_CASE("UVs: u around the axis, v along it (cylinder); around both circles (torus)", "[quadric]") {
    RayStats st;
    auto cyl = one(cylinder({0, 0, 0}, {0, 2, 0}, 1));
    // From -z towards the axis at height 0.5: the point (0, 0.5, -1), u = 0.5 as the sphere map's.
    Ray ray{{0, 0.5, -5}, {0, 0, 1}};
    auto hit = cyl->intersect(ray, 1e300, st);
    REQUIRE(hit);
    SurfaceHit s = cyl->surface(ray, *hit);
    CHECK(s.uv.x == Approx(0.5));
    CHECK(s.uv.y == Approx(0.25));
    CHECK(s.p_object.y == Approx(0.5));
    auto tor = one(torus(1, 0.25));
    // The top of the tube at +x: u = 0.75 (as the sphere map's at +x), v = 0.25 (a quarter turn
    // from the outer equator towards +y).
    ray = {{1, 5, 0}, {0, -1, 0}};
    hit = tor->intersect(ray, 1e300, st);
    REQUIRE(hit);
    s = tor->surface(ray, *hit);
    CHECK(s.p.y == Approx(0.25));
    CHECK(s.uv.x == Approx(0.75));
    CHECK(s.uv.y == Approx(0.25));
}

TEST_CASE("R66 torus rays that graze the tube", "[quadric][robust]") {
    // Lines tangent to the outer equator, to the top circle and to the hole's rim, moved towards
    // the tube or away from it by 1e-12 … 1e-4 of the size: towards hits, away misses, and every
    // hit lies on the surface.
    const double major = 1, minor = 0.25;
    auto g = one(torus(major, minor));
    RayStats st;
    Rng rng(66);
    int wrong = 0;
    double worst = 0;
    const int n = ray_budget(20000);
    for (int i = 0; i < n; ++i) {
        const double phi = rng.uniform(0, 2 * kPi);
        const double off = rng.log_uniform(-12, -4) * (rng.uniform() < 0.5 ? -1 : 1);
        const Vec3 radial(std::cos(phi), 0, std::sin(phi)), along(-std::sin(phi), 0, std::cos(phi));
        Ray ray;
        switch (i % 3) {
            case 0:  // the outer equator, along its tangent
                ray = {(major + minor - off) * radial - 10.0 * along, along};
                break;
            case 1:  // the top circle, along its tangent
                ray = {major * radial + Vec3(0, minor - off, 0) - 10.0 * along, along};
                break;
            default:  // the hole's rim, vertically
                ray = {(major - minor + off) * radial + Vec3(0, 10, 0), {0, -1, 0}};
                break;
        }
        auto hit = g->intersect(ray, 1e300, st);
        if (bool(hit) != (off > 0)) ++wrong;
        if (hit) worst = std::max(worst, std::abs(torus_distance(major, minor, ray.o + hit->t * ray.d)));
    }
    CHECK(wrong == 0);
    CHECK(worst < 1e-14);
}

TEST_CASE("R67 torus rays from 1e5 radii away", "[quadric][robust]") {
    const double major = 1, minor = 0.3;
    auto g = one(torus(major, minor, rotate_xyz({25, 10, 0})));
    // Far origins: the same silhouette area as the near grid, and hits on the surface.
    const Vec3 dir = glm::normalize(Vec3(0.2, -1, 0.3));
    const Grid near = grid_along(dir, {0, 0, 0}, 3, 300, 10);
    Grid far = near;
    far.back = 1e5 * (major + minor);
    CHECK(coverage(*g, far) == Approx(coverage(*g, near)).epsilon(2e-3));
    Rng rng(11);
    RayStats st;
    int hits = 0;
    const Mat4 inv = glm::inverse(rotate_xyz({25, 10, 0}));
    for (int i = 0; i < ray_budget(2000); ++i) {
        const Vec3 o = 1e5 * (major + minor) * rng.unit_vector();
        const Ray ray{o, rng.in_box(Vec3(-1.3), Vec3(1.3)) - o};
        auto hit = g->intersect(ray, 1e300, st);
        if (!hit) continue;
        ++hits;
        const Vec3 p = Vec3(inv * glm::dvec4(ray.o + hit->t * ray.d, 1));
        // The point itself is known only to a few ULPs of 1e5: the root is that accurate.
        CHECK(std::abs(torus_distance(major, minor, p)) < 1e-9);
    }
    CHECK(hits > ray_budget(200));
}

TEST_CASE("R68 tori from 1e-110 to 1e30 give the same image up to scale", "[quadric][robust]") {
    // The quartic's coefficients go with the fourth power of the size: 1e-110 underflows them
    // unless the roots are found in the torus's own units.
    const Grid unit = grid_along({0.3, -1, 0.45}, {0, 0, 0}, 3, 200, 10);
    std::vector<uint8_t> reference;
    for (double s : {1.0, 1e-3, 1e3, 0x1p-10, 0x1p10, 0x1p-365, 1e-110, 0x1p100, 1e30}) {
        auto g = one(torus(1 * s, 0.3 * s));
        Grid grid = unit;
        grid.side *= s;
        grid.back *= s;
        std::vector<uint8_t> mask;
        RayStats st;
        for (int j = 0; j < grid.n; ++j)
            for (int i = 0; i < grid.n; ++i) mask.push_back(g->intersect(grid.ray(i, j), 1e300, st) ? 1 : 0);
        if (reference.empty()) {
            reference = mask;
            continue;
        }
        size_t differ = 0;
        for (size_t k = 0; k < mask.size(); ++k) differ += mask[k] != reference[k];
        INFO("scale " << s << ": " << differ << " rays differ");
        // Powers of two scale every operation exactly; powers of ten move rays by a rounding.
        int e = 0;
        if (std::frexp(s, &e) == 0.5)
            CHECK(differ == 0);
        else
            CHECK(differ <= 2);
    }
}

TEST_CASE("R69 a cylinder seen exactly along its axis and exactly edge-on", "[quadric][robust]") {
    auto g = one(cylinder({0, 0, 0}, {0, 2, 0}, 1));
    RayStats st;
    // Along the axis: every ray inside the radius meets the top cap at exactly t = 3, with a
    // normal along the axis; the axis itself too.
    for (double x : {0.0, 0.5, 0.999999, -0.7}) {
        const Ray ray{{x, 5, 0}, {0, -1, 0}};
        auto hit = g->intersect(ray, 1e300, st);
        REQUIRE(hit);
        CHECK(hit->t == 3);
        const SurfaceHit s = g->surface(ray, *hit);
        CHECK(s.ng == Vec3(0, 1, 0));
        CHECK(s.p.y == 2);
    }
    CHECK_FALSE(g->intersect({{1.000001, 5, 0}, {0, -1, 0}}, 1e300, st));
    // Edge-on, in the planes of the caps: the body's rim, not a miss and not a cap.
    for (double y : {0.0, 2.0}) {
        const Ray ray{{0, y, -5}, {0, 0, 1}};
        auto hit = g->intersect(ray, 1e300, st);
        REQUIRE(hit);
        CHECK(hit->t == Approx(4));
        const SurfaceHit s = g->surface(ray, *hit);
        CHECK(s.ng.z == Approx(-1));
    }
    // A ray leaving the wall from inside an open tube, along it: no self-hit.
    auto tube = one(cylinder({0, 0, 0}, {0, 2, 0}, 1, true));
    const Ray in{{0, 1, -5}, {0, 0, 1}};
    auto first = tube->intersect(in, 1e300, st);
    REQUIRE(first);
    const SurfaceHit s = tube->surface(in, *first);
    const Vec3 o = Geometry::offset_origin(s, Vec3(0, 0, 1));
    auto second = tube->intersect({o, {0, 0, 1}}, 1e300, st);
    REQUIRE(second);
    CHECK((o + second->t * Vec3(0, 0, 1)).z == Approx(1));
}

TEST_CASE("R70 rays through a cone's apex", "[quadric][robust]") {
    auto g = one(cone({0, 0, 0}, 1, {0, 2, 0}, 0));
    RayStats st;
    // Down the axis: the apex at t = 3 (a double root), with a finite normal.
    const Ray down{{0, 5, 0}, {0, -1, 0}};
    auto hit = g->intersect(down, 1e300, st);
    REQUIRE(hit);
    CHECK(hit->t == Approx(3).epsilon(1e-12));
    const SurfaceHit s = g->surface(down, *hit);
    CHECK(is_finite(s.ng));
    CHECK(is_finite(s.p));
    // Through the apex from every side: a hit at the apex (never beyond it on the far side, which
    // would be a hole), or, for lines outside the cone, possibly a miss.
    Rng rng(3);
    for (int i = 0; i < 500; ++i) {
        const Vec3 dir = rng.unit_vector();
        const Ray ray{Vec3(0, 2, 0) - 4.0 * dir, dir};
        auto h = g->intersect(ray, 1e300, st);
        // Inside the cone's half-angle below the apex the line enters the solid there.
        // The cone's half-angle is atan(0.5); lines within a margin of a generatrix run along
        // the surface and may meet it anywhere.
        const double off_axis = std::acos(std::abs(dir.y));
        const double half = std::atan(0.5);
        if (off_axis < half - 1e-3) REQUIRE(h);
        if (h && std::abs(off_axis - half) > 1e-3) {
            CHECK(h->t <= 4 + 1e-9);
            const SurfaceHit sh = g->surface(ray, *h);
            CHECK(is_finite(sh.ng));
        }
    }
}

TEST_CASE("quadric_crossings gives every crossing of the whole line, alternating in and out", "[quadric]") {
    QuadricPrim q;
    Mat4 frame;
    REQUIRE_FALSE(make_quadric(torus(1, 0.25), q, frame));
    double t[4];
    int part[4];
    // Along the x axis through the centre: four crossings at ±0.75, ±1.25.
    int n = quadric_crossings(q, {-5, 0, 0}, {1, 0, 0}, t, part, 4);
    REQUIRE(n == 4);
    CHECK(t[0] == Approx(3.75));
    CHECK(t[1] == Approx(4.25));
    CHECK(t[2] == Approx(5.75));
    CHECK(t[3] == Approx(6.25));
    // Behind the origin too.
    n = quadric_crossings(q, {5, 0, 0}, {1, 0, 0}, t, part, 4);
    REQUIRE(n == 4);
    CHECK(t[0] == Approx(-6.25));
    // A closed cylinder along its axis: base cap then top cap.
    REQUIRE_FALSE(make_quadric(cylinder({0, 0, 0}, {0, 0, 3}, 1), q, frame));
    // Canonical frame: the axis is +y, from 0 to h = 3.
    n = quadric_crossings(q, {0.5, -1, 0}, {0, 1, 0}, t, part, 4);
    REQUIRE(n == 2);
    CHECK(t[0] == 1);
    CHECK(part[0] == kQuadricBaseCap);
    CHECK(t[1] == 4);
    CHECK(part[1] == kQuadricTopCap);
    const QuadricPoint p = quadric_part_surface(q, part[1], {0.5, -1, 0}, {0, 1, 0}, t[1]);
    CHECK(p.n == Vec3(0, 1, 0));
    CHECK(p.p.y == 3);
}

TEST_CASE("bad quadric specs are build errors, not crashes", "[quadric]") {
    std::vector<ShapeSpec> bad = {cylinder({0, 0, 0}, {0, 0, 0}, 1),
                                  cylinder({0, 0, 0}, {0, 1, 0}, 0),
                                  cone({0, 0, 0}, 0, {0, 1, 0}, 0),
                                  cone({0, 0, 0}, -1, {0, 1, 0}, 1),
                                  torus(0, 1),
                                  torus(1, std::nan("")),
                                  disc({0, 0, 0}, {0, 0, 0}, 1, 0),
                                  disc({0, 0, 0}, {0, 1, 0}, 1, 1)};
    for (const ShapeSpec& s : bad) {
        std::vector<SpecError> errors;
        CHECK_FALSE(Geometry::build(scene_of({s}), errors));
        CHECK(errors.size() == 1);
    }
}

TEST_CASE("cylinders and cones seen from 1e5 radii away: hits on the surface", "[quadric][robust]") {
    // Before the roots were taken from the line's point nearest the body, the cone's b² − ac lost
    // its digits to b² ≈ 10¹⁰ and its hits strayed 7e-5 from the surface.
    Rng rng(67);
    for (double top : {1.0, 0.2}) {
        ShapeSpec s = top == 1.0 ? cylinder({0, -1, 0}, {0, 1, 0}, 1) : cone({0, -1, 0}, 1, {0, 1, 0}, top);
        auto g = one(s);
        RayStats st;
        int hits = 0;
        double worst = 0;
        const double k = (top - 1) / 2;
        for (int i = 0; i < ray_budget(5000); ++i) {
            const Vec3 o = 1e5 * rng.unit_vector();
            const Ray ray{o, rng.in_box(Vec3(-1.2), Vec3(1.2)) - o};
            auto hit = g->intersect(ray, 1e300, st);
            if (!hit || int(hit->b1) != kQuadricBody) continue;
            ++hits;
            const Vec3 p = ray.o + hit->t * ray.d;
            const double radius = 1 + k * (p.y + 1);
            worst = std::max(worst, std::abs(std::hypot(p.x, p.z) - radius) / std::sqrt(1 + k * k));
        }
        INFO("cap radius " << top);
        CHECK(hits > ray_budget(1000));
        CHECK(worst < 1e-9);
    }
}
