// The abstract syntax tree: what the parser builds and the interpreter walks. Every node has a
// span. Large lists of numeric vector literals (mesh vertices and faces) are stored packed —
// numbers plus each element's source offset — instead of one heap node per number.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lang/source.h"

namespace wsd::lang {

struct Expr;
struct Stmt;
struct Block;
using ExprPtr = std::unique_ptr<Expr>;
using StmtPtr = std::unique_ptr<Stmt>;

enum class ExprKind {
    Number,      // number
    String,      // text (escapes already decoded)
    Bool,        // boolean (`true` / `false`)
    Ident,       // text = name
    Vector,      // args = 2 or 3 components
    List,        // args = elements
    PackedList,  // packed = a list whose elements are all numeric vector literals of one size
    Unary,       // unary_op, args[0]; op_span = the operator
    Binary,      // args = 2 or more operands, ops = the operators between them (one level)
    Call,        // text = function name, op_span = the name, args = arguments
    Member,      // text = field name (x y z r g b u v), op_span = the name, args[0] = operand
    Index,       // args[0] = operand, args[1] = index; op_span = the '['
    Material,    // block = the material block (`material { ... }`)
    Image,       // args[0] = path expression (`image "file.png"`)
    Checker,     // block (`checker { ... }`)
    Perlin,      // block (`perlin { ... }`)
    Bad,         // placeholder after a syntax error: later passes skip it
};

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

// One operator of a binary chain, with its span (where its errors point).
struct BinaryLink {
    BinaryOp op;
    Span span;
};

struct Expr {
    ExprKind kind = ExprKind::Bad;
    Span span;
    double number = 0;
    bool boolean = false;
    std::string text;
    UnaryOp unary_op = UnaryOp::Neg;
    Span op_span;
    std::vector<BinaryLink> ops;  // Binary: ops[i] stands between args[i] and args[i + 1]
    std::vector<ExprPtr> args;
    std::unique_ptr<Block> block;
    std::shared_ptr<const PackedVectors> packed;
};

// One `name value, value, ...` item of a block. A triangle's leading vertices form an item with
// an empty name. Values are expressions; enumerated values (`kind marble`, `sampling uniform`) are
// Ident expressions whose name the interpreter reads as a word.
struct Item {
    std::string name;
    Span name_span;
    std::vector<ExprPtr> values;
};

// `{ item item ... }`. Blocks only hold items; statements never appear inside them.
struct Block {
    Span open;   // the '{'
    Span close;  // the '}' (or where it was expected)
    std::vector<Item> items;
};

enum class StmtKind { Let, For, If, Include, Block, Bad };
enum class BlockKind { Settings, Camera, Light, Sphere, Box, Triangle, Plane, Mesh };

struct IfBranch {
    ExprPtr condition;  // null for the final `else`
    std::vector<StmtPtr> body;
    Span keyword;  // `if` or `else`
};

struct Stmt {
    StmtKind kind = StmtKind::Bad;
    Span span;
    // Let: name = value. For: name in value .. range_end, or name in value (a list).
    // Include: name = the path (decoded), name_span = the string literal.
    // Block: block_kind; for lights name = the kind word (`point`, `area`), name_span its span.
    std::string name;
    Span name_span;
    ExprPtr value;
    ExprPtr range_end;
    std::vector<IfBranch> branches;  // If
    std::vector<StmtPtr> body;       // For
    BlockKind block_kind = BlockKind::Settings;
    Span keyword;  // the statement's first token
    Block block;
};

struct Program {
    uint32_t file = 0;
    std::vector<StmtPtr> statements;
};

// Deterministic dump: an indented S-expression, one node per line, each with @LINE:COL.
std::string print_ast(const Program& program, const SourceManager& sources);

}  // namespace wsd::lang
