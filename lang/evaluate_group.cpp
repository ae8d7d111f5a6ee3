// Object values: an object block evaluated into a value instead of being added (a leaf lowered
// with its material optional, since what encloses it may give one), group and CSG bodies run as
// scopes whose object statements add members, `object EXPR { ... }` instances, the solid check of
// CSG members, and delivery of a value where objects go (the body being evaluated, or the scene).
#include <algorithm>

#include "lang/interpreter.h"
#include "lang/object_value.h"
#include "render/memory_budget.h"
#include "render/mesh_topology.h"

namespace wsd::lang {

namespace {

// Why a CSG member is not a solid ("'disc'"), with a help line when there is more to say.
std::optional<std::string> not_solid(const ObjectValue& v, std::string& help) {
    switch (v.kind) {
        case ObjectKind::Csg:
            return std::nullopt;
        case ObjectKind::Group:
            return std::string("'group'");
        case ObjectKind::Instance:
            return not_solid(*v.target, help);
        case ObjectKind::Leaf:
            break;
    }
    const render::ShapeSpec& s = v.leaf->shape;
    const std::string quoted = std::string(1, '\'').append(shape_word(s.kind)).append(1, '\'');
    switch (s.kind) {
        case render::ShapeKind::Triangle:
        case render::ShapeKind::Disc:
            return quoted;
        case render::ShapeKind::Cylinder:
        case render::ShapeKind::Cone:
            if (s.open) return std::string("an open ").append(quoted);
            return std::nullopt;
        case render::ShapeKind::Mesh:
            if (s.mesh)
                if (auto problem = render::closed_mesh_problem(*s.mesh)) {
                    help = *problem;
                    return std::string("'mesh'");
                }
            return std::nullopt;
        default:
            return std::nullopt;
    }
}

ObjectKind kind_of(GroupKind kind) {
    return kind == GroupKind::Group ? ObjectKind::Group : ObjectKind::Csg;
}

render::CsgOp op_of(GroupKind kind) {
    return kind == GroupKind::Intersection ? render::CsgOp::Intersection
           : kind == GroupKind::Difference ? render::CsgOp::Difference
                                           : render::CsgOp::Union;
}

}  // namespace

std::optional<Value> Interpreter::eval_object(const ObjectExpr& expr) {
    ObjectPtr value = object_value(*expr.object);
    if (!value) return std::nullopt;
    return Value::make_object(std::move(value), expr.span);
}

ObjectPtr Interpreter::object_value(const Stmt& stmt) {
    switch (stmt.kind) {
        case StmtKind::Object:
            return leaf_value(stmt.as<ObjectStmt>());
        case StmtKind::Group:
            return group_value(stmt.as<GroupStmt>());
        case StmtKind::Instance:
            return instance_value(stmt.as<InstanceStmt>());
        default:
            return nullptr;
    }
}

ObjectPtr Interpreter::leaf_value(const ObjectStmt& stmt) {
    const BlockTable* table = statement_table(stmt, diags_);
    if (!table) return nullptr;
    BlockReader block = eval_block(*table, stmt.block, stmt.keyword);
    BlockContext ctx = context();
    ctx.material_optional = true;
    std::optional<LoweredObject> object = lower_object(block, ctx);
    if (!object) return nullptr;
    auto value = std::make_shared<ObjectValue>();
    value->keyword = stmt.keyword;
    value->chain = chain_;
    value->material = object->material;
    if (const Binding* b = find("default_material")) {
        value->fallback.defined_at = b->span;
        if (!b->value)
            value->fallback.failed = true;
        else if (!b->value->is(ValueType::Material))
            value->fallback.wrong_type = type_name(b->value->type());
        else
            value->fallback.material = b->value->material();
    }
    value->objects = 1;
    value->triangles = object->is_triangle                             ? 1
                       : object->shape.kind == render::ShapeKind::Mesh ? object->primitives
                                                                       : 0;
    value->solid_primitives = object->primitives;
    value->leaf = std::move(object);
    return value;
}

ObjectPtr Interpreter::group_value(const GroupStmt& stmt) {
    const char* word = group_keyword(stmt.group_kind);
    BlockReader items(block_table(word), stmt.keyword, stmt.open, stmt.close, diags_);
    std::vector<ObjectPtr> members;
    std::vector<ObjectPtr>* saved_members = members_;
    const GroupStmt* saved_body = body_;
    members_ = &members;
    body_ = &stmt;
    // The body's objects build this value, also inside a call made from an expression
    // (`return group { leg() }`); a call from an expression within the body is checked afresh.
    const CallExpr* saved_expression_call = std::exchange(expression_call_, nullptr);
    const size_t errors_before = diags_.error_count();
    push_scope();
    for (const Stmt* s : stmt.body) {
        if (stopped()) break;
        if (s->kind == StmtKind::Item) {
            eval_item(items, s->as<ItemStmt>().item);
        } else {
            exec(*s);
        }
    }
    pop_scope();
    members_ = saved_members;
    body_ = saved_body;
    expression_call_ = saved_expression_call;
    // A body with errors has no value: its members are incomplete, and what uses it would only
    // report the same errors again.
    if (stopped() || !items.ok() || diags_.error_count() != errors_before) return nullptr;
    auto value = std::make_shared<ObjectValue>();
    value->kind = kind_of(stmt.group_kind);
    value->op = op_of(stmt.group_kind);
    value->keyword = stmt.keyword;
    value->chain = chain_;
    if (const Value* m = items.value("material")) value->material = m->material();
    value->transform = compose_transforms(items.transforms());
    value->members = std::move(members);
    for (const ObjectPtr& m : value->members) {
        value->objects += m->objects;
        value->triangles += m->triangles;
        value->depth = std::max(value->depth, m->depth + 1);
    }
    if (!check_depth(*value)) return nullptr;
    if (value->kind == ObjectKind::Csg) {
        value->objects = 1;  // one solid
        for (const ObjectPtr& m : value->members)
            value->solid_primitives = value->solid_primitives > SIZE_MAX - m->solid_primitives
                                          ? SIZE_MAX
                                          : value->solid_primitives + m->solid_primitives;
        // Its members are copied into it: a recursion doubling a CSG would outgrow memory.
        if (value->solid_primitives > limits_.primitives) {
            diags_.error(stmt.keyword,
                         "this '" + std::string(word) + "' has more than " +
                             std::to_string(limits_.primitives) +
                             " primitives (the limit; nested CSG and instances in it are copies)");
            abort();
            return nullptr;
        }
        if (!check_csg_members(*value, word)) return nullptr;
    }
    return value;
}

bool Interpreter::check_csg_members(const ObjectValue& csg, const std::string& word) {
    if (csg.members.empty()) {
        Diagnostic& d = diags_.error(csg.keyword, "empty '" + word + "': CSG needs at least one solid");
        d.help.push_back(
            "add the solids it combines: sphere, box, cylinder, cone, torus, plane, a closed mesh");
        return false;
    }
    bool ok = true;
    for (const ObjectPtr& m : csg.members) {
        std::string help;
        if (auto what = not_solid(*m, help)) {
            Diagnostic& d = diags_.error(m->keyword, *what + " is not a solid; CSG needs closed shapes");
            d.notes.push_back({csg.keyword, "in this '" + word + "'"});
            if (!help.empty()) d.help.push_back(help);
            ok = false;
            if (diags_.too_many()) break;
        }
    }
    return ok;
}

bool Interpreter::check_depth(const ObjectValue& value) {
    if (value.depth <= kMaxObjectDepth) return true;
    diags_.error(value.keyword, "object values nested too deep (the limit is " +
                                    std::to_string(kMaxObjectDepth) +
                                    " levels of groups, CSG and instances)");
    abort();
    return false;
}

ObjectPtr Interpreter::instance_value(const InstanceStmt& stmt) {
    std::optional<Value> target = eval(*stmt.value);
    BlockReader items = eval_block(block_table("object"), stmt.block, stmt.keyword);
    if (!target) return nullptr;
    if (!target->is(ValueType::Object)) {
        Diagnostic& d = diags_.error(stmt.value->span, std::string("'object' needs an object value, found ") +
                                                           type_name(target->type()));
        if (target->is(ValueType::List))
            d.help.push_back("to add every object of a list, write 'for o in LIST { object o { } }'");
        else
            d.help.push_back(
                "an object value is an object block, e.g. 'let ball = sphere { ... }', then "
                "'object ball { ... }'");
        return nullptr;
    }
    if (!items.ok()) return nullptr;
    auto value = std::make_shared<ObjectValue>();
    value->kind = ObjectKind::Instance;
    value->keyword = stmt.keyword;
    value->chain = chain_;
    value->target = target->object();
    if (const Value* m = items.value("material")) value->material = m->material();
    value->transform = compose_transforms(items.transforms());
    value->objects = value->target->objects;
    value->triangles = value->target->triangles;
    value->solid_primitives = value->target->solid_primitives;
    value->depth = value->target->depth + 1;
    if (!check_depth(*value)) return nullptr;
    return value;
}

bool Interpreter::instances_fit(size_t instances, Span added_by) {
    // Each instance is a ShapeSpec while the scene loads (about 520 bytes); what the build adds
    // afterwards is estimated, and checked, once the scene is complete (render/memory_budget.h).
    const render::MemoryAvailable available = render::available_memory();
    if (!available.error.empty() || !available.bytes) return true;  // reported, or unknown
    const size_t need = instances * sizeof(render::ShapeSpec);
    if (need <= *available.bytes) return true;
    Diagnostic& d =
        diags_.error(added_by, "the scene's " + std::to_string(instances) + " instances need about " +
                                   render::memory_text(need) + " while it loads, more than the " +
                                   render::memory_text(*available.bytes) + " of " + available.source);
    d.help.push_back("instances of groups of instances multiply: each level's count is a factor");
    return false;
}

void Interpreter::deliver(const ObjectPtr& value, Span added_by) {
    if (members_) {
        members_->push_back(value);
        return;
    }
    // Refused before it is made when its instances alone cross a limit (a recursion builds
    // exponentially many in a few steps).
    SceneBuilder::Expansion grows = scene_.expansion(value);
    grows += {scene_.instances(), scene_.primitives()};
    if (grows.instances >= next_memory_check_ && grows.instances <= limits_.instances) {
        while (next_memory_check_ <= grows.instances) next_memory_check_ *= 2;
        if (!instances_fit(grows.instances, added_by)) return abort();
    }
    if (grows.instances <= limits_.instances && grows.copies <= limits_.primitives)
        scene_.add_object_value(value, added_by, diags_);
    if (scene_.primitives() > limits_.primitives || grows.copies > limits_.primitives) {
        diags_.error(added_by, "the scene has more than " + std::to_string(limits_.primitives) +
                                   " primitives (the limit; a mesh counts its triangles, stored once per "
                                   "distinct value)");
        abort();
    } else if (scene_.instances() > limits_.instances || grows.instances > limits_.instances) {
        diags_.error(added_by, "the scene has more than " + std::to_string(limits_.instances) +
                                   " instances (the limit)");
        abort();
    }
}

}  // namespace wsd::lang
