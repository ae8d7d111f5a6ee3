// Block evaluation: the items of a block statement or a `material`/`checker`/`perlin` expression
// evaluated in order into an evaluated block, each checked against the block's table as it is
// evaluated (so diagnostics come in source order, and an item the table rejects is not
// evaluated), then handed to lowering. `image "file"` evaluates its path, then lowers it.
#include "lang/interpreter.h"

namespace wsd::lang {

BlockReader Interpreter::eval_block(const BlockTable& table, const Block& block, Span keyword) {
    size_t values = 0;
    for (const Item& item : block.items) values += item.values.size();
    BlockReader reader(table, keyword, block.open, block.close, diags_, block.items.size(), values);
    for (const Item& item : block.items) {
        if (diags_.too_many()) {
            reader.failed();
            break;
        }
        eval_item(reader, item);
    }
    return reader;
}

void Interpreter::eval_item(BlockReader& reader, const Item& item) {
    // Free again before any value is evaluated (a nested block's evaluation reuses it).
    value_spans_.clear();
    for (const Expr* e : item.values) value_spans_.push_back(e->span);
    const ItemRead read = reader.admit(item.name, item.name_span, value_spans_);
    for (const Expr* e : item.values) {
        if (read == ItemRead::Skip) break;
        if (read == ItemRead::Evaluate) {
            reader.accept({eval(*e), e->span, false});
        } else if (e->kind == ExprKind::Ident) {
            const std::string_view word = e->as<IdentExpr>().name;
            reader.accept({Value::make_string(std::string(word), e->span), e->span, true});
        } else {
            reader.accept({std::nullopt, e->span, false});
        }
    }
    reader.end_item();
}

std::optional<Value> Interpreter::eval_block_expr(const BlockExpr& expr) {
    BlockReader block = eval_block(expression_table(expr.kind), *expr.block, head_span(expr));
    BlockContext ctx = context();
    if (expr.kind == ExprKind::Material) {
        MaterialPtr m = lower_material(block, ctx);
        if (!m) return std::nullopt;
        Span span = m->block.keyword;
        return Value::make_material(std::move(m), span);
    }
    TexturePtr t = lower_texture(block, ctx);
    if (!t) return std::nullopt;
    return Value::make_texture(std::move(t), expr.span);
}

std::optional<Value> Interpreter::eval_image(const ImageExpr& expr) {
    std::optional<Value> path = eval(*expr.path);
    if (!path) return std::nullopt;
    BlockContext ctx = context();
    TexturePtr t = lower_image(*path, expr.path->span, ctx);
    if (!t) return std::nullopt;
    if (named_image_paths_.insert(t->spec.image_path).second) named_images_.push_back(t);
    return Value::make_texture(std::move(t), expr.span);
}

}  // namespace wsd::lang
