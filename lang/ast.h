// The abstract syntax tree: what the parser builds and the interpreter walks. Each production
// has its own node type with its span and only its fields (Go's cmd/compile/internal/syntax
// nodes.go is the model). Nodes are allocated in the Program's arena and linked by plain pointers:
// a tree of any shape is freed at once, without recursion, and a node costs only its fields.
//
// Passes dispatch with a switch over the node's kind tag and `as<T>()`, not with a visitor: each
// pass keeps its cases together in one function with its own arguments and results (a visitor
// would force one signature on every pass), and as those switches have no `default:`, -Wswitch
// names every pass that does not handle a new kind yet. Adding a node kind is an enum value, a
// struct, and the cases the compiler asks for. Large lists of numeric vector literals (mesh
// vertices and faces) are stored packed — numbers plus each element's source offset — instead of
// one node per number.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "lang/arena.h"
#include "lang/source.h"

namespace wsd::lang {

enum class UnaryOp { Neg, Not };
enum class BinaryOp { Or, And, Eq, Ne, Lt, Le, Gt, Ge, Add, Sub, Mul, Div, Mod };

// The operator as written in source ("||", "<=", "%", ...).
inline const char* binary_op_text(BinaryOp op) {
    switch (op) {
        case BinaryOp::Or:
            return "||";
        case BinaryOp::And:
            return "&&";
        case BinaryOp::Eq:
            return "==";
        case BinaryOp::Ne:
            return "!=";
        case BinaryOp::Lt:
            return "<";
        case BinaryOp::Le:
            return "<=";
        case BinaryOp::Gt:
            return ">";
        case BinaryOp::Ge:
            return ">=";
        case BinaryOp::Add:
            return "+";
        case BinaryOp::Sub:
            return "-";
        case BinaryOp::Mul:
            return "*";
        case BinaryOp::Div:
            return "/";
        case BinaryOp::Mod:
            return "%";
    }
    return "?";
}

struct PackedVectors {
    int dims = 3;                   // 2 or 3
    std::vector<double> values;     // dims numbers per element
    std::vector<uint32_t> offsets;  // byte offset of each element's '<' in its file
    uint32_t file = 0;
    size_t size() const { return offsets.size(); }
};

// ---- expressions --------------------------------------------------------------------------------

enum class ExprKind : uint8_t {
    Number,      // NumberExpr
    String,      // StringExpr
    Bool,        // BoolExpr
    Ident,       // IdentExpr
    Vector,      // VectorExpr
    List,        // ListExpr
    PackedList,  // PackedListExpr: a list whose elements are all numeric vector literals of one size
    Unary,       // UnaryExpr
    Binary,      // BinaryExpr
    Call,        // CallExpr
    Member,      // MemberExpr
    Index,       // IndexExpr
    Material,    // BlockExpr (`material { ... }`)
    Image,       // ImageExpr (`image "file.png"`)
    Checker,     // BlockExpr (`checker { ... }`)
    Perlin,      // BlockExpr (`perlin { ... }`)
    Object,      // ObjectExpr: an object block written as a value
    Bad,         // Expr alone: a placeholder after a syntax error (the program is never run)
};

// `as<T>()`, the downcast of a node head to its node type: the head's kind tag says which it is.
template <class Head>
struct Downcast {
    template <class T>
    const T& as() const {
        return static_cast<const T&>(static_cast<const Head&>(*this));
    }
    template <class T>
    T& as() {
        return static_cast<T&>(static_cast<Head&>(*this));
    }
};

// The common head of every expression node.
struct Expr : Downcast<Expr> {
    ExprKind kind;
    Span span;
};

using ExprList = std::span<Expr* const>;

struct NumberExpr : Expr {
    double value;
};
struct StringExpr : Expr {
    std::string_view text;  // escapes already decoded
};
struct BoolExpr : Expr {
    bool value;
};
struct IdentExpr : Expr {
    std::string_view name;
};
struct VectorExpr : Expr {
    ExprList components;  // 2 or 3
};
struct ListExpr : Expr {
    ExprList elements;
};
struct PackedListExpr : Expr {
    std::shared_ptr<const PackedVectors> packed;  // shared with list values: never copied
};
struct UnaryExpr : Expr {
    UnaryOp op;
    Span op_span;
    Expr* operand;
};
// One operator of a binary chain, with its span (where its errors point).
struct BinaryLink {
    BinaryOp op;
    Span span;
};
// Operators of one precedence level in a row: `a - b + c` is operands {a, b, c} and ops {-, +},
// meaning ((a - b) + c). Two or more operands; the chain is flat, so its length costs no stack.
struct BinaryExpr : Expr {
    ExprList operands;
    std::span<const BinaryLink> ops;  // ops[i] stands between operands[i] and operands[i + 1]
};
struct CallExpr : Expr {
    std::string_view name;
    Span name_span;
    ExprList args;
};
struct MemberExpr : Expr {
    Expr* operand;
    std::string_view field;  // x y z r g b u v
    Span field_span;
};
struct IndexExpr : Expr {
    Expr* operand;
    Expr* index;
    Span bracket;  // the '['
};
struct Block;
struct BlockExpr : Expr {  // Material, Checker, Perlin
    Block* block;
};
struct ImageExpr : Expr {
    Expr* path;
};
struct Stmt;
// An object block (sphere, ..., `group`, CSG, `object EXPR { ... }`) where an expression is
// expected: the same node as the statement, whose value it is instead of being added.
struct ObjectExpr : Expr {
    Stmt* object;  // an ObjectStmt (never settings, camera or light), GroupStmt or InstanceStmt
};

// ---- blocks -------------------------------------------------------------------------------------

// One `name value, value, ...` item of a block. A triangle's leading vertices form an item with
// an empty name. Enumerated values (`kind marble`, `sampling uniform`) are Ident expressions
// whose name the interpreter reads as a word.
struct Item {
    std::string_view name;
    Span name_span;
    ExprList values;
};

// `{ item item ... }`. Blocks only hold items; statements never appear inside them.
struct Block {
    Span open;   // the '{'
    Span close;  // the '}' (or where it was expected)
    std::span<const Item> items;
};

// ---- statements ---------------------------------------------------------------------------------

enum class StmtKind : uint8_t { Let, For, If, Include, Object, Group, Instance, Item, Fn, Return, Call, Bad };
enum class BlockKind : uint8_t {
    Settings,
    Camera,
    Light,
    Sphere,
    Box,
    Triangle,
    Plane,
    Mesh,
    Cylinder,
    Cone,
    Torus,
    Disc
};

// The common head of every statement node; `keyword` is its first token.
struct Stmt : Downcast<Stmt> {
    StmtKind kind;
    Span span;
    Span keyword;
};

using StmtList = std::span<Stmt* const>;

struct LetStmt : Stmt {
    std::string_view name;  // empty after a syntax error
    Span name_span;
    Expr* value;  // never null (Bad after a syntax error)
};
// `for name in value .. range_end { body }`, or `for name in value { body }` (range_end null).
struct ForStmt : Stmt {
    std::string_view name;
    Span name_span;
    Expr* value;  // never null
    Expr* range_end;
    StmtList body;
};
struct IfBranch {
    Expr* condition;  // null for the final `else`
    StmtList body;
    Span keyword;  // `if` or `else`
};
struct IfStmt : Stmt {
    std::span<const IfBranch> branches;
};
struct IncludeStmt : Stmt {
    std::string_view path;  // decoded
    Span path_span;         // the string literal
};
// settings, camera, light, sphere, box, triangle, plane, mesh.
struct ObjectStmt : Stmt {
    BlockKind block_kind;
    std::string_view name;  // lights: the kind word (`point`, `area`)
    Span name_span;
    Block block;
};

enum class GroupKind : uint8_t { Group, Union, Intersection, Difference };
// `group { ... }`, `union { ... }`, `intersection { ... }`, `difference { ... }`: a body of
// statements and ItemStmts (material, scale, rotate, translate), in the order written.
struct GroupStmt : Stmt {
    GroupKind group_kind;
    Span open, close;
    StmtList body;
};
// `object EXPR { items }`: an instance of an object value.
struct InstanceStmt : Stmt {
    Expr* value;  // never null (Bad after a syntax error)
    Block block;
};
// One item of a group or CSG body, among its statements.
struct ItemStmt : Stmt {
    Item item;
};

// The keyword of a group kind ("group", "union", ...).
inline const char* group_keyword(GroupKind kind) {
    switch (kind) {
        case GroupKind::Group:
            return "group";
        case GroupKind::Union:
            return "union";
        case GroupKind::Intersection:
            return "intersection";
        case GroupKind::Difference:
            return "difference";
    }
    return "group";
}
// One parameter of a `fn`; `fallback` is its default value (null: the argument is required).
struct Param {
    std::string_view name;
    Span name_span;
    Expr* fallback;
};
// `fn name(params) { body }`. Parameters with a default come after those without one.
struct FnStmt : Stmt {
    std::string_view name;  // empty after a syntax error
    Span name_span;
    std::span<const Param> params;
    StmtList body;
    size_t required() const {  // the number of parameters without a default
        size_t n = 0;
        while (n < params.size() && !params[n].fallback) ++n;
        return n;
    }
};
// `return value`; the parser allows it only inside a `fn` body.
struct ReturnStmt : Stmt {
    Expr* value;  // never null
};
// `name(args)` alone on a statement.
struct CallStmt : Stmt {
    CallExpr* call;  // never null
};

struct Program {
    uint32_t file = 0;
    StmtList statements;
    std::unique_ptr<Arena> arena = std::make_unique<Arena>();  // owns every node of the tree
};

// Deterministic dump: an indented S-expression, one node per line, each with @LINE:COL.
std::string print_ast(const Program& program, const SourceManager& sources);

}  // namespace wsd::lang
