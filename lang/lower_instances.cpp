// Object values into the render spec: a group added as a statement is flattened into world shapes
// (each member's transforms first, then the group's), `object` of a group or a mesh adds Instance
// shapes of one prototype per distinct value (and per material variant), a single primitive or a
// CSG added by `object` is copied (it is no more than its one shape), so is a plane in an instanced
// group (it has no bounds for the prototype's tree), and a CSG becomes one Csg
// shape whose members are in its own frame. Prototypes never contain instances: an `object` inside
// an instanced group becomes an instance of its own at the top level, with composed transforms.
//
// Material inheritance: a surface uses its own object's material, else the one of the nearest
// enclosing group, CSG or `object` that gives one, else the `default_material` in scope where its
// block was evaluated. Where what gives it is an instance or a CSG, the spec says so with
// kInheritMaterial, so a prototype or a CSG is shared by every material it is added with.
#include <map>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "lang/object_value.h"

namespace wsd::lang {

namespace {

// What an enclosing group, CSG or `object` gives a member without a material of its own.
struct Inherit {
    enum class From { Nothing, Material, Container } from = From::Nothing;
    MaterialPtr material;  // From::Material
    bool gives() const { return from != From::Nothing; }
};

Inherit own_or(const ObjectValue& v, const Inherit& outer) {
    return v.material ? Inherit{Inherit::From::Material, v.material} : outer;
}

// An `object` nested in an instanced group: placed again wherever that group is placed.
struct SubInstance {
    ObjectPtr instance;  // the `object` that adds it (where its instances are reported), or the plane
    ObjectPtr target;    // a group, a mesh, or a plane (copied per instance)
    render::Mat4 transform;
    Inherit inherit;  // Container: the enclosing instance's material
};

// Where shapes go: the world (instances are added there directly) or a prototype (instances are
// collected in `subs`, to be placed with each instance of the prototype).
struct Out {
    std::vector<render::ShapeSpec>* shapes;
    std::vector<SubInstance>* subs;
};

}  // namespace

class ObjectLowering {
public:
    explicit ObjectLowering(SceneBuilder& b) : b_(b) {}

    void add(const ObjectPtr& value, Span added_by, Diagnostics& diags) {
        diags_ = &diags;
        added_by_ = added_by;
        b_.scene_.summary.objects += value->objects;
        b_.scene_.summary.triangles += value->triangles;
        walk(value, render::Mat4(1.0), Inherit{}, Out{&b_.scene_.spec.shapes, nullptr});
    }

    // What adding `value` to the world makes beyond what its evaluation counted: instance shapes,
    // and planes copied once per instance. Found from the value graph before any is made, since a
    // recursive function builds in a few steps a value whose instances outnumber memory.
    SceneBuilder::Expansion expansion(const ObjectPtr& value) {
        switch (value->kind) {
            case ObjectKind::Leaf:
            case ObjectKind::Csg:
                return {};
            case ObjectKind::Group: {
                SceneBuilder::Expansion e;
                for (const ObjectPtr& m : value->members) e += expansion(m);
                return e;
            }
            case ObjectKind::Instance:
                break;
        }
        const ObjectPtr& t = unwrap(value);
        if (t->kind == ObjectKind::Csg || (t->kind == ObjectKind::Leaf && !t->is_mesh())) return {};
        return instanced(t);
    }

private:
    static const ObjectPtr& unwrap(const ObjectPtr& v) {
        const ObjectPtr* t = &v;
        while ((*t)->kind == ObjectKind::Instance) t = &(*t)->target;
        return *t;
    }
    static bool is_plane(const ObjectValue& v) {
        return v.kind == ObjectKind::Leaf && v.leaf->shape.kind == render::ShapeKind::Plane;
    }

    // Instances of a group or mesh `t` placed once: its prototype's, and its nested ones.
    SceneBuilder::Expansion instanced(const ObjectPtr& t) {
        if (t->is_mesh()) return {1, 0};
        if (auto it = expansions_.find(t.get()); it != expansions_.end()) return it->second;
        SceneBuilder::Expansion e = nested(*t);
        if (has_geometry(*t)) e += {1, 0};
        kept_.push_back(t);
        expansions_.emplace(t.get(), e);
        return e;
    }
    // What the members of group `g` add per instance of it outside its prototype.
    SceneBuilder::Expansion nested(const ObjectValue& g) {
        SceneBuilder::Expansion e;
        for (const ObjectPtr& m : g.members) {
            if (m->kind == ObjectKind::Group) {
                e += nested(*m);
            } else if (m->kind == ObjectKind::Instance) {
                const ObjectPtr& u = unwrap(m);
                if (is_plane(*u))
                    e += {0, 1};
                else if (u->kind != ObjectKind::Csg && !(u->kind == ObjectKind::Leaf && !u->is_mesh()))
                    e += instanced(u);
            } else if (is_plane(*m)) {
                e += {0, 1};
            }
        }
        return e;
    }
    // Whether group `g`'s prototype holds a shape (else only its nested instances are placed).
    static bool has_geometry(const ObjectValue& g) {
        for (const ObjectPtr& m : g.members) {
            const ObjectValue& u = *unwrap(m);
            if (m->kind == ObjectKind::Group
                    ? has_geometry(*m)
                    : u.kind == ObjectKind::Csg || (u.kind == ObjectKind::Leaf && !is_plane(u) &&
                                                    (m->kind == ObjectKind::Leaf || !u.is_mesh())))
                return true;
        }
        return false;
    }

    struct Prototype {
        std::optional<uint32_t> index;  // none: the value has no geometry outside nested instances
        std::vector<SubInstance> subs;
    };
    struct Csg {
        std::shared_ptr<const render::CsgSpec> spec;
        uint32_t some_material = 0;  // a member's: for a CSG whose members all have their own
    };
    using Key = std::pair<const ObjectValue*, bool>;  // the value, and whether its material is inherited

    void walk(const ObjectPtr& v, const render::Mat4& m, const Inherit& inherit, Out out) {
        switch (v->kind) {
            case ObjectKind::Leaf:
                if (out.subs && v->leaf->shape.kind == render::ShapeKind::Plane) {
                    // A plane has no bounds for a prototype's tree: each instance adds a copy.
                    out.subs->push_back({v, v, m, inherit});
                    return;
                }
                emit_leaf(*v, m, inherit, *out.shapes);
                return;
            case ObjectKind::Group: {
                const render::Mat4 inner = m * v->transform;
                const Inherit given = own_or(*v, inherit);
                for (const ObjectPtr& member : v->members) walk(member, inner, given, out);
                return;
            }
            case ObjectKind::Csg:
                emit_csg(v, m, inherit, out, false);
                return;
            case ObjectKind::Instance:
                place(v, m, inherit, out);
                return;
        }
    }

    // `object V { ... }`: V's own transforms and material, then the instance's, then `m`.
    void place(const ObjectPtr& instance, const render::Mat4& m, const Inherit& inherit, Out out) {
        ObjectPtr target = instance;
        render::Mat4 placed = m;
        Inherit given = inherit;
        while (target->kind == ObjectKind::Instance) {
            placed = placed * target->transform;
            given = own_or(*target, given);
            target = target->target;
        }
        if (target->kind == ObjectKind::Csg || (target->kind == ObjectKind::Leaf && !target->is_mesh())) {
            walk(target, placed, given, out);  // one shape: a copy costs what an instance would
        } else if (out.subs) {
            out.subs->push_back({instance, target, placed, given});
        } else {
            instantiate(*instance, target, placed, given);
        }
    }

    // Instances of `target` (a group or a mesh) in the world: its prototype, and its nested ones.
    void instantiate(const ObjectValue& instance, const ObjectPtr& target, const render::Mat4& m,
                     const Inherit& inherit) {
        if (target->kind == ObjectKind::Leaf && !target->is_mesh()) {  // a plane of an instanced group
            emit_leaf(*target, m, inherit, b_.scene_.spec.shapes);
            return;
        }
        const bool inherited = inherit.gives() && takes_material(*target);
        const Prototype& p = prototype(target, inherited);
        if (p.index) {
            render::ShapeSpec s;
            s.kind = render::ShapeKind::Instance;
            s.prototype = *p.index;
            s.object_to_world = m;
            s.material = inherited ? b_.material_index(inherit.material) : render::kInheritMaterial;
            s.tag = instance_tag(instance);
            b_.scene_.spec.shapes.push_back(std::move(s));
            ++b_.instances_;
        }
        for (const SubInstance& sub : p.subs)
            instantiate(*sub.instance, sub.target, m * sub.transform,
                        sub.inherit.from == Inherit::From::Container ? inherit : sub.inherit);
    }

    // Whether some surface of `v` has no material from `v` itself (so that what adds it matters):
    // a value that gives all its own needs one prototype, whatever it is added with.
    bool takes_material(const ObjectValue& v) {
        if (v.material) return false;
        if (auto it = takes_material_.find(&v); it != takes_material_.end()) return it->second;
        bool takes = false;
        switch (v.kind) {
            case ObjectKind::Leaf:
                takes = true;
                break;
            case ObjectKind::Instance:
                takes = takes_material(*v.target);
                break;
            case ObjectKind::Group:
            case ObjectKind::Csg:
                for (const ObjectPtr& m : v.members) takes = takes || takes_material(*m);
                break;
        }
        takes_material_.emplace(&v, takes);
        return takes;
    }

    const Prototype& prototype(const ObjectPtr& target, bool inherited) {
        const Key key{target.get(), inherited};
        if (auto it = prototypes_.find(key); it != prototypes_.end()) return it->second;
        kept_.push_back(target);  // the key's identity must outlive the value's last binding
        render::PrototypeSpec spec;
        std::vector<SubInstance> subs;
        const Inherit root = inherited ? Inherit{Inherit::From::Container, nullptr} : Inherit{};
        walk(target, render::Mat4(1.0), root, Out{&spec.shapes, &subs});
        Prototype p;
        if (!spec.shapes.empty()) {
            spec.tag = b_.record(record_of(*target));
            p.index = static_cast<uint32_t>(b_.scene_.spec.prototypes.size());
            b_.scene_.spec.prototypes.push_back(std::move(spec));
        }
        p.subs = std::move(subs);
        return prototypes_.emplace(key, std::move(p)).first->second;
    }

    void emit_leaf(const ObjectValue& v, const render::Mat4& m, const Inherit& inherit,
                   std::vector<render::ShapeSpec>& shapes) {
        const std::optional<uint32_t> material = leaf_material(v, inherit);
        if (!material) return;
        render::ShapeSpec s = v.leaf->shape;
        s.object_to_world = m * s.object_to_world;
        s.material = *material;
        SpanRecord r = v.leaf->record;
        r.chain = v.chain;
        s.tag = b_.record(std::move(r), v.leaf->fields);
        b_.primitives_ += v.leaf->primitives;
        shapes.push_back(std::move(s));
    }

    // A CSG as one shape; `in_csg`: it is a member of another (its members are expanded there).
    void emit_csg(const ObjectPtr& v, const render::Mat4& m, const Inherit& inherit, Out out, bool in_csg) {
        const Inherit given = own_or(*v, inherit);
        if (v->op == render::CsgOp::Difference && v->members.size() == 1) {  // that member
            if (in_csg)
                csg_member(v->members[0], m * v->transform, given, *out.shapes);
            else
                walk(v->members[0], m * v->transform, given, out);
            return;
        }
        const Csg& csg = csg_of(v, given.gives());
        render::ShapeSpec s;
        s.kind = render::ShapeKind::Csg;
        s.csg = csg.spec;
        s.object_to_world = m * v->transform;
        s.material = given.from == Inherit::From::Material    ? b_.material_index(given.material)
                     : given.from == Inherit::From::Container ? render::kInheritMaterial
                                                              : csg.some_material;
        s.tag = b_.record(record_of(*v));
        out.shapes->push_back(std::move(s));
    }

    // A CSG's members in its frame, once per value and per whether its material is given.
    const Csg& csg_of(const ObjectPtr& v, bool given) {
        const Key key{v.get(), given};
        if (auto it = csgs_.find(key); it != csgs_.end()) return it->second;
        kept_.push_back(v);
        auto spec = std::make_shared<render::CsgSpec>();
        spec->op = v->op;
        const Inherit members = given ? Inherit{Inherit::From::Container, nullptr} : Inherit{};
        for (const ObjectPtr& member : v->members)
            csg_member(member, render::Mat4(1.0), members, spec->members);
        Csg csg;
        for (const render::ShapeSpec& s : spec->members)
            if (s.material != render::kInheritMaterial) {
                csg.some_material = s.material;
                break;
            }
        csg.spec = std::move(spec);
        return csgs_.emplace(key, std::move(csg)).first->second;
    }

    // Members are solids (checked when the CSG was evaluated): leaves, CSGs, instances of those.
    void csg_member(const ObjectPtr& v, const render::Mat4& m, const Inherit& inherit,
                    std::vector<render::ShapeSpec>& members) {
        switch (v->kind) {
            case ObjectKind::Leaf:
                emit_leaf(*v, m, inherit, members);
                return;
            case ObjectKind::Csg:
                emit_csg(v, m, inherit, Out{&members, nullptr}, true);
                return;
            case ObjectKind::Instance:
                csg_member(v->target, m * v->transform, own_or(*v, inherit), members);
                return;
            case ObjectKind::Group:
                return;
        }
    }

    // The material index of a leaf's surfaces; nothing after reporting that it has none.
    std::optional<uint32_t> leaf_material(const ObjectValue& v, const Inherit& inherit) {
        if (v.material) return b_.material_index(v.material);
        if (inherit.from == Inherit::From::Material) return b_.material_index(inherit.material);
        if (inherit.from == Inherit::From::Container) return render::kInheritMaterial;
        const FallbackMaterial& f = v.fallback;
        if (f.material) return b_.material_index(f.material);
        if (f.failed || !reported_.insert(&v).second) return std::nullopt;
        const std::string what = shape_word(v.leaf->shape.kind);
        Diagnostic* d;
        if (f.wrong_type) {
            d = &diags_->error(v.keyword,
                               std::string("'default_material' is a ") + f.wrong_type + ", not a material");
            d->notes.push_back({f.defined_at, "'default_material' is defined here"});
        } else {
            d = &diags_->error(v.keyword, "missing property 'material' in " + what);
            d->help.push_back("add 'material { ... }' or 'let default_material = material { ... }'");
        }
        if (added_by_.file != v.keyword.file || added_by_.begin != v.keyword.begin)
            d->notes.push_back({added_by_, "added here, and nothing enclosing it gives a material"});
        return std::nullopt;
    }

    SpanRecord record_of(const ObjectValue& v) const {
        SpanRecord r;
        r.span = v.keyword;
        r.chain = v.chain;
        return r;
    }

    // One span record per `object` statement (and include chain), however many instances it adds.
    uint32_t instance_tag(const ObjectValue& instance) {
        const auto key = std::make_tuple(instance.keyword.file, instance.keyword.begin, instance.chain.get());
        if (auto it = instance_tags_.find(key); it != instance_tags_.end()) return it->second;
        const uint32_t tag = b_.record(record_of(instance));
        instance_tags_.emplace(key, tag);
        return tag;
    }

    SceneBuilder& b_;
    Diagnostics* diags_ = nullptr;
    Span added_by_;
    std::map<std::tuple<uint32_t, uint32_t, const IncludeSite*>, uint32_t> instance_tags_;
    std::map<Key, Prototype> prototypes_;  // node-based: references stay valid while it grows
    std::map<Key, Csg> csgs_;
    std::vector<ObjectPtr> kept_;
    std::unordered_map<const ObjectValue*, bool> takes_material_;  // of values kept alive in kept_
    std::unordered_map<const ObjectValue*, SceneBuilder::Expansion> expansions_;  // likewise
    std::unordered_set<const ObjectValue*> reported_;
};

// Here, where ObjectLowering is complete.
SceneBuilder::SceneBuilder(uint32_t main_file) {
    // Tag 0: the start of the main file, for errors about elements without a source.
    SpanRecord start;
    start.span = Span{main_file, 0, 0};
    scene_.spans.push_back(std::move(start));
}

SceneBuilder::~SceneBuilder() = default;

void SceneBuilder::drop_object_caches() {
    objects_.reset();
}

void SceneBuilder::add_object_value(const ObjectPtr& value, Span added_by, Diagnostics& diags) {
    if (!objects_) objects_ = std::make_unique<ObjectLowering>(*this);
    objects_->add(value, added_by, diags);
}

SceneBuilder::Expansion SceneBuilder::expansion(const ObjectPtr& value) {
    if (!objects_) objects_ = std::make_unique<ObjectLowering>(*this);
    return objects_->expansion(value);
}

}  // namespace wsd::lang
