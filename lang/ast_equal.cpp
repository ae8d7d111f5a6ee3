// Node by node, as print_ast would print them: kinds, names, operators, values and children;
// spans are ignored. A packed list equals a packed list with the same numbers.
#include "lang/ast_equal.h"

namespace wsd::lang {

namespace {

bool same(const Expr& a, const Expr& b);
bool same(const Stmt& a, const Stmt& b);

template <class T, class Eq>
bool same_list(std::span<T> a, std::span<T> b, Eq eq) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!eq(a[i], b[i])) return false;
    return true;
}

bool same_ptr(const Expr* a, const Expr* b) {
    return (!a && !b) || (a && b && same(*a, *b));
}

bool same_exprs(ExprList a, ExprList b) {
    return same_list(a, b, [](const Expr* x, const Expr* y) { return same(*x, *y); });
}

bool same_stmts(StmtList a, StmtList b) {
    return same_list(a, b, [](const Stmt* x, const Stmt* y) { return same(*x, *y); });
}

bool same_item(const Item& a, const Item& b) {
    return a.name == b.name && same_exprs(a.values, b.values);
}

bool same_block(const Block& a, const Block& b) {
    return same_list(a.items, b.items, same_item);
}

bool same(const Expr& a, const Expr& b) {
    if (a.kind != b.kind) return false;
    switch (a.kind) {
        case ExprKind::Number:
            return a.as<NumberExpr>().value == b.as<NumberExpr>().value;
        case ExprKind::String:
            return a.as<StringExpr>().text == b.as<StringExpr>().text;
        case ExprKind::Bool:
            return a.as<BoolExpr>().value == b.as<BoolExpr>().value;
        case ExprKind::Ident:
            return a.as<IdentExpr>().name == b.as<IdentExpr>().name;
        case ExprKind::Bad:
            return true;
        case ExprKind::Vector:
            return same_exprs(a.as<VectorExpr>().components, b.as<VectorExpr>().components);
        case ExprKind::List:
            return same_exprs(a.as<ListExpr>().elements, b.as<ListExpr>().elements);
        case ExprKind::PackedList: {
            const PackedVectors& x = *a.as<PackedListExpr>().packed;
            const PackedVectors& y = *b.as<PackedListExpr>().packed;
            return x.dims == y.dims && x.values == y.values && x.size() == y.size();
        }
        case ExprKind::Unary:
            return a.as<UnaryExpr>().op == b.as<UnaryExpr>().op &&
                   same(*a.as<UnaryExpr>().operand, *b.as<UnaryExpr>().operand);
        case ExprKind::Binary: {
            const auto& x = a.as<BinaryExpr>();
            const auto& y = b.as<BinaryExpr>();
            return same_list(x.ops, y.ops,
                             [](const BinaryLink& p, const BinaryLink& q) { return p.op == q.op; }) &&
                   same_exprs(x.operands, y.operands);
        }
        case ExprKind::Call:
            return a.as<CallExpr>().name == b.as<CallExpr>().name &&
                   same_exprs(a.as<CallExpr>().args, b.as<CallExpr>().args);
        case ExprKind::Member:
            return a.as<MemberExpr>().field == b.as<MemberExpr>().field &&
                   same(*a.as<MemberExpr>().operand, *b.as<MemberExpr>().operand);
        case ExprKind::Index:
            return same(*a.as<IndexExpr>().operand, *b.as<IndexExpr>().operand) &&
                   same(*a.as<IndexExpr>().index, *b.as<IndexExpr>().index);
        case ExprKind::Material:
        case ExprKind::Checker:
        case ExprKind::Perlin:
            return same_block(*a.as<BlockExpr>().block, *b.as<BlockExpr>().block);
        case ExprKind::Image:
            return same(*a.as<ImageExpr>().path, *b.as<ImageExpr>().path);
        case ExprKind::Object:
            return same(*a.as<ObjectExpr>().object, *b.as<ObjectExpr>().object);
    }
    return false;
}

bool same(const Stmt& a, const Stmt& b) {
    if (a.kind != b.kind) return false;
    switch (a.kind) {
        case StmtKind::Let:
            return a.as<LetStmt>().name == b.as<LetStmt>().name &&
                   same(*a.as<LetStmt>().value, *b.as<LetStmt>().value);
        case StmtKind::For: {
            const auto& x = a.as<ForStmt>();
            const auto& y = b.as<ForStmt>();
            return x.name == y.name && same(*x.value, *y.value) && same_ptr(x.range_end, y.range_end) &&
                   same_stmts(x.body, y.body);
        }
        case StmtKind::If:
            return same_list(a.as<IfStmt>().branches, b.as<IfStmt>().branches,
                             [](const IfBranch& x, const IfBranch& y) {
                                 return same_ptr(x.condition, y.condition) && same_stmts(x.body, y.body);
                             });
        case StmtKind::Include:
            return a.as<IncludeStmt>().path == b.as<IncludeStmt>().path;
        case StmtKind::Object: {
            const auto& x = a.as<ObjectStmt>();
            const auto& y = b.as<ObjectStmt>();
            return x.block_kind == y.block_kind && x.name == y.name && same_block(x.block, y.block);
        }
        case StmtKind::Group:
            return a.as<GroupStmt>().group_kind == b.as<GroupStmt>().group_kind &&
                   same_stmts(a.as<GroupStmt>().body, b.as<GroupStmt>().body);
        case StmtKind::Instance:
            return same(*a.as<InstanceStmt>().value, *b.as<InstanceStmt>().value) &&
                   same_block(a.as<InstanceStmt>().block, b.as<InstanceStmt>().block);
        case StmtKind::Item:
            return same_item(a.as<ItemStmt>().item, b.as<ItemStmt>().item);
        case StmtKind::Fn: {
            const auto& x = a.as<FnStmt>();
            const auto& y = b.as<FnStmt>();
            return x.name == y.name &&
                   same_list(x.params, y.params,
                             [](const Param& p, const Param& q) {
                                 return p.name == q.name && same_ptr(p.fallback, q.fallback);
                             }) &&
                   same_stmts(x.body, y.body);
        }
        case StmtKind::Return:
            return same(*a.as<ReturnStmt>().value, *b.as<ReturnStmt>().value);
        case StmtKind::Call:
            return same(*a.as<CallStmt>().call, *b.as<CallStmt>().call);
        case StmtKind::Bad:
            return true;
    }
    return false;
}

}  // namespace

bool same_ast(const Program& a, const Program& b) {
    return same_stmts(a.statements, b.statements);
}

}  // namespace wsd::lang
