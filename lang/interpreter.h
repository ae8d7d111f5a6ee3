// The interpreter: walks the AST with lexical scopes, runs let/for/if/include/fn and calls,
// evaluates expressions into values and blocks into evaluated blocks (checked against their tables
// as they are evaluated), then hands each to lowering, collecting the scene in a SceneBuilder.
// Object statements deliver where objects go: the scene, or the group or CSG body being evaluated
// (whose value they build: lang/object_value.h). Errors go to Diagnostics; evaluation continues
// past independent errors and stops at limits, failed includes and "too many errors".
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "lang/ast.h"
#include "lang/builtins.h"
#include "lang/diagnostics.h"
#include "lang/environment.h"
#include "lang/lower.h"
#include "lang/value.h"
#include "render/limits.h"

namespace wsd::lang {

class ParamTable;

// Reads an included file into `text`; false with the reason (lower case) when it cannot. An
// editor's reader gives its unsaved text. (The same alias is declared in lang/load.h.)
using IncludeReader = std::function<bool(const std::string& path, std::string& text, std::string& reason)>;

struct Limits {
    uint64_t loop_iterations = 100'000'000;      // in total, with one step per function call
    size_t primitives = render::kMaxPrimitives;  // stored: distinct geometry
    size_t instances = render::kMaxInstances;
    int include_depth = 64;
    // The parser limits nesting to 256 levels a file (a chain of one operator level is one
    // node); this guards the evaluator's own recursion over the whole scene, where includes
    // nested in bodies add up (statements and expressions counted together). A function call
    // starts a new count: the evaluator runs on a stack sized for call_depth such counts.
    int eval_depth = 600;
    int call_depth = 256;  // nested calls of user functions
};

class Interpreter {
public:
    Interpreter(SourceManager& sources, Diagnostics& diags, SceneBuilder& scene, Limits limits = {});
    ~Interpreter();

    // Runs the main file of a scene (its file id is the scene's first include-cycle entry).
    void run(const Program& program);
    // The --define values that `param` returns; the table must outlive the run.
    void set_params(const ParamTable* params) { params_ = params; }
    // Where included files are read from (an editor's unsaved text); the file system when unset.
    void set_file_reader(const IncludeReader* reader) { reader_ = reader; }
    // Where the path of each mesh file read is added, read or not; none when unset.
    void set_mesh_files(std::vector<std::string>* files) { mesh_files_ = files; }
    // The values of the built-in constants `clock` and `frame` (a still's 0 and 0 by default).
    void set_time(const AnimationTime& time) { time_ = time; }
    // A flag that stops the run at the next loop iteration or call once it holds true (a signal
    // during a long evaluation); cancelled() then says so. Nothing is reported.
    void set_cancel(const std::atomic<bool>* flag) { cancel_ = flag; }
    bool cancelled() const { return cancelled_; }
    // Evaluates one expression in the current (top) scope.
    std::optional<Value> evaluate(const Expr& expr);
    // A binding of the file's top scope (for tests); nullopt if absent or failed.
    std::optional<Value> lookup(std::string_view name) const;

    bool aborted() const { return aborted_; }
    bool camera_seen() const { return first_camera_.has_value(); }  // even one with errors
    uint64_t iterations() const { return iterations_; }
    // Each image file that an `image` texture evaluated here names (the first texture per path),
    // used by an object or not: load_scene reads them all.
    const std::vector<TexturePtr>& named_images() const { return named_images_; }
    // Scopes that outlived their code and are still held (by functions): for tests.
    size_t escaped_scopes_alive() const {
        size_t n = 0;
        for (const std::weak_ptr<Scope>& w : escaped_) n += w.expired() ? 0 : 1;
        return n;
    }

private:
    using Binding = lang::Binding;
    using Included = lang::Included;
    using Scope = lang::Scope;
    // Counts statement and expression recursion together; past the limit evaluation stops with
    // one error instead of overflowing the stack.
    class DepthGuard {
    public:
        DepthGuard(Interpreter& in, Span at);
        ~DepthGuard() { --in_.depth_; }
        DepthGuard(const DepthGuard&) = delete;
        DepthGuard& operator=(const DepthGuard&) = delete;
        bool ok() const { return ok_; }

    private:
        Interpreter& in_;
        bool ok_;
    };

    // statements
    void exec_all(StmtList body);
    void exec(const Stmt& stmt);
    void exec_let(const LetStmt& stmt);
    void exec_for(const ForStmt& stmt);
    void exec_if(const IfStmt& stmt);
    void exec_include(const IncludeStmt& stmt);
    // Every statement that adds an object (a block, a group or CSG, an `object`) comes here.
    void exec_object(const Stmt& stmt);
    void exec_fn(const FnStmt& stmt);
    void exec_return(const ReturnStmt& stmt);
    void exec_call(const CallStmt& stmt);
    bool run_loop_body(const ForStmt& stmt, const Value& item);
    bool take_iterations(double count, Span at);

    // expressions
    std::optional<Value> eval(const Expr& expr);
    std::optional<Value> eval_ident(const IdentExpr& expr);
    std::optional<Value> eval_vector(const VectorExpr& expr);
    std::optional<Value> eval_list(const ListExpr& expr);
    std::optional<Value> eval_unary(const UnaryExpr& expr);
    std::optional<Value> eval_binary(const BinaryExpr& expr);
    std::optional<Value> eval_logical(const BinaryExpr& expr);
    std::optional<Value> eval_call(const CallExpr& expr);
    std::vector<std::string> callable_names() const;  // for "did you mean"

    // user functions (functions.cpp)
    std::optional<Value> call_function(const FunctionPtr& fn, const CallExpr& call, bool in_expression);
    bool check_arity(const FunctionValue& fn, const CallExpr& call);
    void call_depth_error(const CallExpr& call);
    bool take_call_step(const CallExpr& call);
    bool bind_arguments(const FnStmt& decl, const CallExpr& call, Scope& frame);
    void drop_call_value(const Value& value, const CallExpr& call);
    // Whether a statement that adds to the scene may run here: not during a call made from an
    // expression (reported at `at`, with a note at that call).
    bool objects_allowed(Span at);
    std::optional<Value> eval_member(const MemberExpr& expr);
    std::optional<Value> eval_index(const IndexExpr& expr);
    // One step of a binary chain: its operator, where its errors point, and its result's span.
    struct BinaryStep {
        BinaryOp op;
        Span op_span;
        Span span;
    };
    std::optional<Value> arithmetic(const BinaryStep& step, const Value& a, const Value& b);
    std::optional<Value> compare(const BinaryStep& step, const Value& a, const Value& b);

    // scopes
    void push_scope();
    void push_scope(ScopePtr parent);  // a scope inside `parent` (a function's body)
    ScopePtr new_scope();
    void pop_scope();
    void bind(std::string_view name, Span span, std::optional<Value> value);
    const Binding* find(std::string_view name) const;
    std::vector<std::string> visible_names() const;

    // object values (evaluate_group.cpp)
    // An object statement's value: a leaf, a group or CSG (its body run as a scope whose object
    // statements add members), or an instance; null after an error (reported).
    ObjectPtr object_value(const Stmt& stmt);
    ObjectPtr leaf_value(const ObjectStmt& stmt);
    ObjectPtr group_value(const GroupStmt& stmt);
    ObjectPtr instance_value(const InstanceStmt& stmt);
    bool check_depth(const ObjectValue& value);
    bool check_csg_members(const ObjectValue& csg, const std::string& word);
    std::optional<Value> eval_object(const ObjectExpr& expr);
    // Adds a value where objects go now: the body being evaluated, or the scene.
    void deliver(const ObjectPtr& value, Span added_by);
    // Whether `instances` instance shapes can be held while the scene loads (checked when the
    // count first passes each doubling from 65,536), else an error at added_by.
    bool instances_fit(size_t instances, Span added_by);
    // Every kMemoryStep loop iterations and calls (taken at `at`): false, having reported an
    // error at `at`, when what the machine can still give is nearly spent (lang/memory_steps.cpp).
    bool take_memory_step(Span at) { return ++memory_steps_ % kMemoryStep != 0 || memory_left(at); }
    bool memory_left(Span at);
    std::string_view keyword_text(const Stmt& s) const;

    // A block's items evaluated in order and checked against `table` as they are.
    BlockReader eval_block(const BlockTable& table, const Block& block, Span keyword);
    // One item evaluated into `reader` (which checks it as it goes).
    void eval_item(BlockReader& reader, const Item& item);
    std::optional<Value> eval_block_expr(const BlockExpr& expr);
    std::optional<Value> eval_image(const ImageExpr& expr);
    // `default_material`: whether to look up that binding (for an object that may need it).
    BlockContext context(bool default_material = false);
    void abort() { aborted_ = true; }
    // True, having stopped the run, when the cancel flag holds true.
    bool cancel_now() {
        if (cancel_ == nullptr || !cancel_->load(std::memory_order_relaxed)) return false;
        cancelled_ = true;
        abort();
        return true;
    }
    bool stopped() const { return aborted_ || diags_.too_many(); }

    SourceManager& sources_;
    Diagnostics& diags_;
    SceneBuilder& scene_;
    Limits limits_;
    const ParamTable* params_ = nullptr;
    AnimationTime time_;
    ScopePtr scope_;                             // the innermost scope of the code that runs
    ScopePtr top_;                               // the main file's top scope
    std::vector<ScopePtr> spare_;                // popped scopes nothing else held, reused by push_scope
    std::vector<std::weak_ptr<Scope>> escaped_;  // popped scopes still held (by functions)
    size_t prune_escaped_at_ = 64;
    void prune_escaped();  // forgets the expired, frees those only their own functions hold
    int depth_ = 0;
    uint64_t iterations_ = 0;
    bool aborted_ = false;
    const std::atomic<bool>* cancel_ = nullptr;
    size_t next_memory_check_ = size_t{1} << 16;  // instances
    // What the scene takes while it loads, whatever makes it (objects, lists, strings): the
    // process's resident memory when the interpreter began and at the last check.
    static constexpr uint32_t kMemoryStep = 16384;
    uint32_t memory_steps_ = 0;
    size_t resident_at_start_ = 0, resident_at_check_ = 0;
    bool cancelled_ = false;
    std::optional<Span> first_settings_, first_camera_;  // the first such statement that ran
    // Where object statements deliver: the members of the group or CSG body being evaluated
    // (body_ names its kind), or the scene (null).
    std::vector<ObjectPtr>* members_ = nullptr;
    const GroupStmt* body_ = nullptr;

    // calls
    std::vector<const CallExpr*> calls_;         // the user-function calls running, outermost first
    const CallExpr* expression_call_ = nullptr;  // the innermost running call made from an expression
    bool returning_ = false;                     // a `return` ran: the body stops
    std::optional<Value> return_value_;

    // includes
    const IncludeReader* reader_ = nullptr;
    IncludeChain chain_;
    int include_depth_ = 0;
    std::vector<std::string> include_stack_;     // canonical paths of the files being run
    std::vector<uint32_t> include_stack_files_;  // their file ids (for the cycle message)
    const Included* visible_include(const std::string& key) const;
    std::unordered_map<std::string, bool> adds_objects_;  // canonical path -> its run added objects
    std::vector<std::unique_ptr<Program>> programs_;      // included ASTs: bindings point into them
    std::unordered_map<std::string, const Program*> parsed_includes_;  // path as resolved -> its AST
    ObjCache obj_cache_;
    std::vector<std::string>* mesh_files_ = nullptr;
    std::vector<TexturePtr> named_images_;
    std::unordered_set<std::string> named_image_paths_;
    std::vector<Span> value_spans_;  // eval_block's scratch: the value spans of the item it admits
};

}  // namespace wsd::lang
