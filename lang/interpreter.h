// The interpreter: walks the AST with lexical scopes, runs let/for/if/include, evaluates
// expressions into values and blocks into evaluated blocks (checked against their tables as they
// are evaluated), then hands each to lowering, collecting the scene in a SceneBuilder. Object
// statements deliver where objects go: the scene, or the group or CSG body being evaluated (whose
// value they build: lang/object_value.h). Errors go to
// Diagnostics; evaluation continues past independent errors and stops at limits, failed includes and "too
// many errors".
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "lang/ast.h"
#include "lang/diagnostics.h"
#include "lang/lower.h"
#include "lang/value.h"
#include "render/limits.h"

namespace wsd::lang {

class ParamTable;

struct Limits {
    uint64_t loop_iterations = 100'000'000;      // in total
    size_t primitives = render::kMaxPrimitives;  // stored: distinct geometry
    size_t instances = render::kMaxInstances;
    int include_depth = 64;
    // The parser limits nesting to 256 levels a file (a chain of one operator level is one
    // node); this guards the evaluator's own recursion over the whole scene, where includes
    // nested in bodies add up (statements and expressions counted together).
    int eval_depth = 600;
};

class Interpreter {
public:
    Interpreter(SourceManager& sources, Diagnostics& diags, SceneBuilder& scene, Limits limits = {});
    ~Interpreter();

    // Runs the main file of a scene (its file id is the scene's first include-cycle entry).
    void run(const Program& program);
    // The --define values that `param` returns; the table must outlive the run.
    void set_params(const ParamTable* params) { params_ = params; }
    // Evaluates one expression in the current (top) scope.
    std::optional<Value> evaluate(const Expr& expr);
    // A binding of the file's top scope (for tests); nullopt if absent or failed.
    std::optional<Value> lookup(std::string_view name) const;

    bool aborted() const { return aborted_; }
    bool camera_seen() const { return first_camera_.has_value(); }  // even one with errors
    uint64_t iterations() const { return iterations_; }

private:
    struct Binding {
        std::string_view name;
        Span span;
        std::optional<Value> value;  // empty: its definition failed (already reported)
    };
    // A file included in this scope: a second include of it here or in an enclosed scope is skipped.
    struct Included {
        std::string key;  // canonical path
        Span site;        // the include that ran it
    };
    struct Scope {
        std::vector<Binding> bindings;
        std::unordered_map<std::string_view, size_t> index;  // built once a scope grows large
        std::vector<Included> included;
        const Binding* find(std::string_view name) const;
        void clear();
    };
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
    bool stopped() const { return aborted_ || diags_.too_many(); }

    SourceManager& sources_;
    Diagnostics& diags_;
    SceneBuilder& scene_;
    Limits limits_;
    const ParamTable* params_ = nullptr;
    std::vector<Scope> scopes_;  // scopes_[0..depth_) are live; the rest are reused storage
    size_t scope_count_ = 0;
    int depth_ = 0;
    uint64_t iterations_ = 0;
    bool aborted_ = false;
    std::optional<Span> first_settings_, first_camera_;  // the first such statement that ran
    // Where object statements deliver: the members of the group or CSG body being evaluated
    // (body_ names its kind), or the scene (null).
    std::vector<ObjectPtr>* members_ = nullptr;
    const GroupStmt* body_ = nullptr;

    // includes
    IncludeChain chain_;
    int include_depth_ = 0;
    std::vector<std::string> include_stack_;     // canonical paths of the files being run
    std::vector<uint32_t> include_stack_files_;  // their file ids (for the cycle message)
    const Included* visible_include(const std::string& key) const;
    std::unordered_map<std::string, bool> adds_objects_;  // canonical path -> its run added objects
    std::vector<std::unique_ptr<Program>> programs_;      // included ASTs: bindings point into them
    ObjCache obj_cache_;
    std::vector<Span> value_spans_;  // eval_block's scratch: the value spans of the item it admits
};

}  // namespace wsd::lang
