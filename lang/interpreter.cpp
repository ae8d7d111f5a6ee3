// The interpreter's statements: let (one binding per name per scope), for (ranges and lists,
// against a global iteration budget), if (untaken branches are never evaluated), include (relative
// paths, once per scope and the scopes it encloses, cycles and depth), and block statements:
// evaluated (evaluate_block.cpp), then lowered and added to the scene, or made object values and
// added to the body being evaluated (evaluate_group.cpp). Scopes are in environment.cpp,
// functions and calls in functions.cpp, expressions in evaluate.cpp.
#include "lang/interpreter.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "lang/builtins.h"
#include "lang/large_stack.h"
#include "lang/load.h"
#include "lang/parser.h"
#include "render/file_util.h"
#include "render/memory_budget.h"
#include "render/text_util.h"

namespace wsd::lang {

// An include file's text; the reason starts in lower case, as it follows "cannot read ...: ".
bool read_include_file(const std::string& path, std::string& text, std::string& reason) {
    render::FileBytes bytes;
    if (!render::read_whole_file(path, bytes, reason)) {
        if (!reason.empty())
            reason[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(reason[0])));
        return false;
    }
    text.assign(bytes.view());
    return true;
}

namespace {

using render::quoted;

bool is_scene_element(const Stmt& s) {
    if (s.kind != StmtKind::Object) return false;
    const BlockKind kind = s.as<ObjectStmt>().block_kind;
    return kind == BlockKind::Settings || kind == BlockKind::Camera || kind == BlockKind::Light;
}

}  // namespace

std::string_view Interpreter::keyword_text(const Stmt& s) const {
    return std::string_view(sources_.file(s.keyword.file).text)
        .substr(s.keyword.begin, s.keyword.end - s.keyword.begin);
}

Interpreter::DepthGuard::DepthGuard(Interpreter& in, Span at) : in_(in) {
    ok_ = ++in_.depth_ <= in_.limits_.eval_depth;
    if (!ok_ && !in_.aborted_) {
        in_.diags_.error(at, "nesting too deep (limit " + std::to_string(in_.limits_.eval_depth) + ")");
        in_.abort();
    }
}

Interpreter::Interpreter(SourceManager& sources, Diagnostics& diags, SceneBuilder& scene, Limits limits)
    : sources_(sources), diags_(diags), scene_(scene), limits_(limits) {
    top_ = scope_ = std::make_shared<Scope>();  // the file's top scope; builtins live outside it
    resident_at_start_ = resident_at_check_ = render::resident_bytes();
}

BlockContext Interpreter::context(bool default_material) {
    BlockContext ctx{sources_, diags_, chain_, {}, &obj_cache_};
    ctx.mesh_files = mesh_files_;
    if (!calls_.empty()) ctx.call = calls_.front()->span;
    if (default_material)
        if (const Binding* b = find("default_material")) ctx.default_material = {&b->value, b->span};
    return ctx;
}

// ---- statements --------------------------------------------------------------------------------

void Interpreter::run(const Program& program) {
    std::string key = canonical_path(sources_.file(program.file).path);
    include_stack_.push_back(key);
    include_stack_files_.push_back(program.file);
    scope_->included.push_back({key, Span{program.file, 0, 0}});
    run_on_large_stack([&] { exec_all(program.statements); });
    include_stack_.pop_back();
    include_stack_files_.pop_back();
}

std::optional<Value> Interpreter::evaluate(const Expr& expr) {
    std::optional<Value> result;
    run_on_large_stack([&] { result = eval(expr); });
    return result;
}

void Interpreter::exec_all(StmtList body) {
    for (const Stmt* s : body) {
        if (stopped() || returning_) return;
        exec(*s);
    }
}

void Interpreter::exec(const Stmt& stmt) {
    DepthGuard guard(*this, stmt.keyword);
    if (!guard.ok()) return;
    switch (stmt.kind) {
        case StmtKind::Let:
            exec_let(stmt.as<LetStmt>());
            break;
        case StmtKind::For:
            exec_for(stmt.as<ForStmt>());
            break;
        case StmtKind::If:
            exec_if(stmt.as<IfStmt>());
            break;
        case StmtKind::Include:
            exec_include(stmt.as<IncludeStmt>());
            break;
        case StmtKind::Object:
        case StmtKind::Group:
        case StmtKind::Instance:
            exec_object(stmt);
            break;
        case StmtKind::Item:
            break;  // read by the group or CSG body that holds it
        case StmtKind::Fn:
            exec_fn(stmt.as<FnStmt>());
            break;
        case StmtKind::Return:
            exec_return(stmt.as<ReturnStmt>());
            break;
        case StmtKind::Call:
            exec_call(stmt.as<CallStmt>());
            break;
        case StmtKind::Bad:
            break;  // the parser reported it
    }
}

void Interpreter::exec_let(const LetStmt& stmt) {
    bind(stmt.name, stmt.name_span, eval(*stmt.value));
}

bool Interpreter::take_iterations(double count, Span at) {
    const double left = static_cast<double>(limits_.loop_iterations - iterations_);
    if (count > left) {
        diags_.error(at, "loop of " + format_number(count) + " iterations exceeds the limit of " +
                             std::to_string(limits_.loop_iterations) + " loop iterations in total (" +
                             format_number(left) + " left)");
        abort();
        return false;
    }
    iterations_ += static_cast<uint64_t>(count);
    return true;
}

// One iteration in a fresh scope; false stops the loop (after an error, so that a broken body is
// reported once rather than once per iteration).
bool Interpreter::run_loop_body(const ForStmt& stmt, const Value& item) {
    if (cancel_now() || !take_memory_step(stmt.span)) return false;
    const size_t errors_before = diags_.error_count();
    push_scope();
    bind(stmt.name, stmt.name_span, item);
    exec_all(stmt.body);
    pop_scope();
    return !stopped() && !returning_ && diags_.error_count() == errors_before;
}

void Interpreter::exec_for(const ForStmt& stmt) {
    if (stmt.range_end) {
        std::optional<Value> a = eval(*stmt.value);
        std::optional<Value> b = eval(*stmt.range_end);
        if (!a || !b) return;
        bool ok = true;
        for (const auto* bound : {&*a, &*b}) {
            const Expr& e = bound == &*a ? *stmt.value : *stmt.range_end;
            if (!bound->is(ValueType::Number)) {
                diags_.error(e.span, std::string("'for' range bounds must be numbers, found ") +
                                         type_name(bound->type()));
                ok = false;
            } else if (bound->number() != std::floor(bound->number())) {
                diags_.error(e.span,
                             "'for' range bounds must be integers, found " + format_number(bound->number()));
                ok = false;
            }
        }
        if (!ok) return;
        const Span range{stmt.value->span.file, stmt.value->span.begin, stmt.range_end->span.end};
        const double first = a->number(), last = b->number();
        const double count = last > first ? last - first : 0.0;
        if (!take_iterations(count, range)) return;
        // An integer counter: `first + k` stays exact where `i += 1` could stall above 2^53.
        const auto n = static_cast<uint64_t>(count);
        for (uint64_t k = 0; k < n; ++k) {
            if (!run_loop_body(stmt, Value::make_number(first + static_cast<double>(k), range))) {
                if (returning_) iterations_ -= n - k - 1;  // a `return` leaves the loop: refund
                break;
            }
        }
        return;
    }
    std::optional<Value> list = eval(*stmt.value);
    if (!list) return;
    if (!list->is(ValueType::List)) {
        diags_.error(stmt.value->span,
                     std::string("'for' needs a list or a range 'A .. B', found ") + type_name(list->type()));
        return;
    }
    const ListPtr items = list->list_ptr();  // keeps the list alive while the body runs
    if (!take_iterations(static_cast<double>(items->size()), stmt.value->span)) return;
    for (size_t i = 0; i < items->size(); ++i) {
        if (!run_loop_body(stmt, items->at(i, sources_))) {
            if (returning_) iterations_ -= items->size() - i - 1;
            break;
        }
    }
}

void Interpreter::exec_if(const IfStmt& stmt) {
    for (const IfBranch& branch : stmt.branches) {
        if (branch.condition) {
            std::optional<Value> c = eval(*branch.condition);
            if (!c) return;
            if (!c->is(ValueType::Bool)) {
                diags_.error(branch.condition->span,
                             std::string("'if' condition must be a bool, found ") + type_name(c->type()));
                return;
            }
            if (!c->boolean()) continue;
        }
        push_scope();
        exec_all(branch.body);
        pop_scope();
        return;
    }
}

void Interpreter::exec_include(const IncludeStmt& stmt) {
    const Span at = stmt.path_span;
    if (include_depth_ >= limits_.include_depth) {
        diags_.error(at, "includes nested too deep (limit " + std::to_string(limits_.include_depth) + ")");
        abort();
        return;
    }
    const std::string path = resolve_path(sources_, at.file, std::string(stmt.path));
    const std::string key = canonical_path(path);
    auto on_stack = std::find(include_stack_.begin(), include_stack_.end(), key);
    if (on_stack != include_stack_.end()) {
        // File names only: the locations (this error and its include notes) give the full paths.
        auto name = [](const std::string& p) { return std::filesystem::path(p).filename().string(); };
        std::string cycle;
        for (size_t i = static_cast<size_t>(on_stack - include_stack_.begin()); i < include_stack_.size();
             ++i)
            cycle += name(sources_.file(include_stack_files_[i]).path) + " → ";
        diags_.error(at, "include cycle: " + cycle + name(path));
        abort();
        return;
    }
    // Once per scope: the names of a file included in this scope or an enclosing one are visible
    // already. Anywhere else (a loop body run again, a sibling block) the include runs again.
    if (const Included* first = visible_include(key)) {
        auto adds = adds_objects_.find(key);
        if (adds != adds_objects_.end() && adds->second) {
            Diagnostic& d = diags_.warning(at, "include of '" + std::string(stmt.path) +
                                                   "' skipped: it was already included in this scope or an "
                                                   "enclosing one, so its objects are not added again");
            if (first->site.end > first->site.begin) d.notes.push_back({first->site, "first included here"});
        }
        return;
    }
    // A file runs again in each scope that includes it (a loop body, say), but it is read and
    // parsed once per scene for each path that names it (paths inside it resolve against that):
    // every run shares that text and AST.
    auto parsed = parsed_includes_.find(path);
    if (parsed == parsed_includes_.end()) {
        std::string text, reason;
        if (!(reader_ && *reader_ ? (*reader_)(path, text, reason) : read_include_file(path, text, reason))) {
            diags_.error(at, "cannot read include file '" + path + "': " + reason);
            abort();
            return;
        }
        const uint32_t file = sources_.add(path, std::move(text));
        diags_.push_include(at);
        const size_t errors_before = diags_.error_count();
        auto program = std::make_unique<Program>(parse(file, sources_, diags_));
        diags_.pop_include();
        const bool ok = diags_.error_count() == errors_before;
        programs_.push_back(std::move(program));
        if (!ok) {
            abort();  // its definitions are missing: running on would only cascade
            return;
        }
        parsed = parsed_includes_.emplace(path, programs_.back().get()).first;
    }
    const Program& program = *parsed->second;
    scope_->included.push_back({key, at});
    // Objects go to the scene (shapes or instances) or to the body being evaluated.
    auto objects_added = [this] {
        return scene_.primitives() + scene_.instances() + (members_ ? members_->size() : 0);
    };
    const size_t objects_before = objects_added();
    diags_.push_include(at);
    include_stack_.push_back(key);
    include_stack_files_.push_back(program.file);
    chain_ = std::make_shared<IncludeSite>(IncludeSite{at, chain_});
    ++include_depth_;
    exec_all(program.statements);  // in the scope where the include stands
    --include_depth_;
    chain_ = chain_->parent;
    include_stack_.pop_back();
    include_stack_files_.pop_back();
    adds_objects_[key] = objects_added() > objects_before;
    diags_.pop_include();
}

void Interpreter::exec_object(const Stmt& added) {
    if (!objects_allowed(added.keyword)) return;
    if (members_ && is_scene_element(added)) {
        const std::string body = group_keyword(body_->group_kind);
        Diagnostic& d = diags_.error(
            added.keyword, "'" + std::string(keyword_text(added)) + "' cannot be in a " + body + " body");
        d.notes.push_back({body_->keyword, "in this '" + body + "'"});
        d.help.push_back("settings, the camera and lights belong to the scene: write them outside");
        return;
    }
    if (members_ || added.kind != StmtKind::Object) {
        if (ObjectPtr value = object_value(added)) deliver(value, added.keyword);
        return;
    }
    const auto& stmt = added.as<ObjectStmt>();
    const BlockTable* table = statement_table(stmt, diags_);
    if (!table) return;
    std::optional<Span>* first = nullptr;  // a settings or camera block
    if (stmt.block_kind == BlockKind::Settings) first = &first_settings_;
    if (stmt.block_kind == BlockKind::Camera) first = &first_camera_;
    // A second settings or camera is an error, but its properties are still checked (then dropped).
    const bool second = first && first->has_value();
    if (second) {
        const bool camera = stmt.block_kind == BlockKind::Camera;
        Diagnostic& d =
            diags_.error(stmt.keyword, camera ? "more than one camera" : "more than one 'settings' block");
        d.notes.push_back(
            {**first, camera ? "the first camera is here" : "the first 'settings' block is here"});
    } else if (first) {
        *first = stmt.keyword;
    }
    BlockReader block = eval_block(*table, stmt.block, stmt.keyword);
    switch (stmt.block_kind) {
        case BlockKind::Settings:
            if (auto s = lower_settings(block); s && !second) scene_.set_settings(*s, stmt.keyword, chain_);
            return;
        case BlockKind::Camera:
            if (auto c = lower_camera(block); c && !second) scene_.set_camera(*c, stmt.keyword, chain_);
            return;
        case BlockKind::Light:
            if (auto l = lower_light(block)) scene_.add_light(*l, stmt.keyword, chain_);
            return;
        default:
            break;
    }
    // Looked up only for an object that names no material of its own.
    BlockContext ctx = context(!block.has("material"));
    std::optional<LoweredObject> object = lower_object(block, ctx);
    if (!object) return;
    if (scene_.primitives() + object->primitives > limits_.primitives) {
        diags_.error(stmt.keyword, "the scene has more than " + std::to_string(limits_.primitives) +
                                       " primitives (the limit; a mesh counts its triangles)");
        abort();
        return;
    }
    scene_.add_object(std::move(*object), chain_);
}

}  // namespace wsd::lang
