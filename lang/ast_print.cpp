// The deterministic AST dump (an indented S-expression, one node per line, each with @LINE:COL;
// the format is documented in tests/golden/README.md) and the recovery of source spans inside
// packed lists, which the dump prints element by element like a generic list.
#include <charconv>

#include "lang/ast.h"
#include "lang/lexer.h"
#include "lang/parser.h"

namespace wsd::lang {

PackedElementSpans packed_element_spans(const PackedVectors& packed, size_t index,
                                        const SourceManager& sources) {
    PackedElementSpans spans;
    const uint32_t file = packed.file;
    Lexer lexer(file, sources.file(file).text, nullptr);
    lexer.reset(packed.offsets.at(index));
    Token t = lexer.next();  // '<'
    spans.element = {file, t.begin, t.end};
    for (int i = 0; i < packed.dims && i < 3; ++i) {
        t = lexer.next();
        spans.minus[i] = {file, t.begin, t.begin};
        if (t.kind == TokenKind::Minus) {
            spans.minus[i].end = t.end;
            t = lexer.next();
        }
        spans.number[i] = {file, t.begin, t.end};
        spans.component[i] = {file, spans.minus[i].begin, t.end};
        spans.count = i + 1;
        t = lexer.next();  // ',' or '>'
    }
    spans.element.end = t.end;
    return spans;
}

namespace {

const char* block_name(BlockKind kind) {
    switch (kind) {
        case BlockKind::Settings:
            return "settings";
        case BlockKind::Camera:
            return "camera";
        case BlockKind::Light:
            return "light";
        case BlockKind::Sphere:
            return "sphere";
        case BlockKind::Box:
            return "box";
        case BlockKind::Triangle:
            return "triangle";
        case BlockKind::Plane:
            return "plane";
        case BlockKind::Mesh:
            return "mesh";
        case BlockKind::Cylinder:
            return "cylinder";
        case BlockKind::Cone:
            return "cone";
        case BlockKind::Torus:
            return "torus";
        case BlockKind::Disc:
            return "disc";
    }
    return "?";
}

std::string format_number(double v) {
    char buf[64];
    const auto result = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, result.ptr);
}

std::string quote_string(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
            case '"':
                out += "\\\"";
                break;
            case '\\':
                out += "\\\\";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            default:
                out += c;
        }
    }
    return out + "\"";
}

// "a b", or "a" when b is empty (a name missing after a syntax error, a triangle's vertices).
std::string join(const std::string& a, std::string_view b) {
    return b.empty() ? a : a + " " + std::string(b);
}

class Printer {
public:
    explicit Printer(const SourceManager& sources) : sources_(sources) {}

    void statement(const Stmt& s);
    std::string out;

private:
    // "(label @L:C" on a new line at the current depth; close() appends the ')'.
    void open(const std::string& label, Span at) {
        if (!out.empty() && out.back() != '\n') out += '\n';
        out.append(2 * static_cast<size_t>(indent_), ' ');
        const LineCol lc = locate(at);
        out += "(" + label + " @" + std::to_string(lc.line) + ":" + std::to_string(lc.column);
        ++indent_;
    }
    void close() {
        out += ')';
        --indent_;
    }
    void leaf(const std::string& label, Span at) {
        open(label, at);
        close();
    }
    void expr(const Expr& e);
    void block(const Block& b);
    void item(const Item& it);
    void packed(const PackedListExpr& e);
    void binary(const BinaryExpr& e);
    void nested(const Expr& e);
    void children(const std::string& label, Span at, ExprList items);

    // line_col, but counting columns on from the previous position when it is on the same line
    // before this one (the usual case: nodes print in source order), so that a dump of a long
    // single-line file is linear, not quadratic.
    LineCol locate(Span at) {
        if (at.file == last_file_ && at.begin >= last_offset_ && have_last_) {
            const auto& starts = sources_.file(at.file).line_starts;
            const bool same_line = last_.line >= starts.size() || at.begin < starts[last_.line];
            if (same_line) {
                last_.column += count_columns(sources_.file(at.file).text, last_offset_, at.begin);
                last_offset_ = at.begin;
                return last_;
            }
        }
        last_ = sources_.line_col(at.file, at.begin);
        last_file_ = at.file;
        last_offset_ = at.begin;
        have_last_ = true;
        return last_;
    }

    const SourceManager& sources_;
    int indent_ = 0;
    bool have_last_ = false;
    uint32_t last_file_ = 0, last_offset_ = 0;
    LineCol last_;
};

void Printer::statement(const Stmt& s) {
    switch (s.kind) {
        case StmtKind::Let: {
            const auto& let = s.as<LetStmt>();
            open(join("let", let.name), s.span);
            expr(*let.value);
            close();
            break;
        }
        case StmtKind::For: {
            const auto& loop = s.as<ForStmt>();
            open(join(join("for", loop.name), loop.range_end ? "range" : "list"), s.span);
            expr(*loop.value);
            if (loop.range_end) expr(*loop.range_end);
            for (const Stmt* b : loop.body) statement(*b);
            close();
            break;
        }
        case StmtKind::If:
            open("if", s.span);
            for (const IfBranch& branch : s.as<IfStmt>().branches) {
                open(branch.condition ? "branch" : "else", branch.keyword);
                if (branch.condition) expr(*branch.condition);
                for (const Stmt* b : branch.body) statement(*b);
                close();
            }
            close();
            break;
        case StmtKind::Include:
            leaf("include " + quote_string(s.as<IncludeStmt>().path), s.span);
            break;
        case StmtKind::Object: {
            const auto& object = s.as<ObjectStmt>();
            std::string label = block_name(object.block_kind);
            if (object.block_kind == BlockKind::Light) label = join(label, object.name);
            open(label, s.span);
            block(object.block);
            close();
            break;
        }
        case StmtKind::Group: {
            const auto& group = s.as<GroupStmt>();
            open(group_keyword(group.group_kind), s.span);
            for (const Stmt* b : group.body) statement(*b);
            close();
            break;
        }
        case StmtKind::Instance: {
            const auto& instance = s.as<InstanceStmt>();
            open("object", s.span);
            expr(*instance.value);
            block(instance.block);
            close();
            break;
        }
        case StmtKind::Item:
            item(s.as<ItemStmt>().item);
            break;
        case StmtKind::Fn: {
            const auto& fn = s.as<FnStmt>();
            open(join("fn", fn.name), s.span);
            for (const Param& p : fn.params) {
                open("param " + std::string(p.name), p.name_span);
                if (p.fallback) expr(*p.fallback);
                close();
            }
            for (const Stmt* b : fn.body) statement(*b);
            close();
            break;
        }
        case StmtKind::Return:
            open("return", s.span);
            expr(*s.as<ReturnStmt>().value);
            close();
            break;
        case StmtKind::Call:
            expr(*s.as<CallStmt>().call);
            break;
        case StmtKind::Bad:
            leaf("bad", s.span);
            break;
    }
}

void Printer::item(const Item& it) {
    open(join("item", it.name), it.name_span);
    for (const Expr* v : it.values) expr(*v);
    close();
}

void Printer::block(const Block& b) {
    for (const Item& it : b.items) item(it);
}

void Printer::expr(const Expr& e) {
    switch (e.kind) {
        case ExprKind::Number:
            leaf("number " + format_number(e.as<NumberExpr>().value), e.span);
            return;
        case ExprKind::String:
            leaf("string " + quote_string(e.as<StringExpr>().text), e.span);
            return;
        case ExprKind::Bool:
            leaf(e.as<BoolExpr>().value ? "bool true" : "bool false", e.span);
            return;
        case ExprKind::Ident:
            leaf("ident " + std::string(e.as<IdentExpr>().name), e.span);
            return;
        case ExprKind::Bad:
            leaf("bad", e.span);
            return;
        case ExprKind::PackedList:
            packed(e.as<PackedListExpr>());
            return;
        case ExprKind::Binary:
            binary(e.as<BinaryExpr>());
            return;
        case ExprKind::Vector:
            children("vector", e.span, e.as<VectorExpr>().components);
            return;
        case ExprKind::List:
            children("list", e.span, e.as<ListExpr>().elements);
            return;
        case ExprKind::Object:
            statement(*e.as<ObjectExpr>().object);
            return;
        case ExprKind::Call: {
            const auto& call = e.as<CallExpr>();
            children("call " + std::string(call.name), e.span, call.args);
            return;
        }
        case ExprKind::Unary:
        case ExprKind::Member:
        case ExprKind::Index:
        case ExprKind::Material:
        case ExprKind::Checker:
        case ExprKind::Perlin:
        case ExprKind::Image:
            nested(e);
            return;
    }
}

// The nodes with one operand or a block inside: the line of the node, then what it holds.
void Printer::nested(const Expr& e) {
    switch (e.kind) {
        case ExprKind::Unary: {
            const auto& u = e.as<UnaryExpr>();
            open(u.op == UnaryOp::Neg ? "unary -" : "unary !", e.span);
            expr(*u.operand);
            break;
        }
        case ExprKind::Member: {
            const auto& m = e.as<MemberExpr>();
            open("member " + std::string(m.field), m.field_span);
            expr(*m.operand);
            break;
        }
        case ExprKind::Index: {
            const auto& ix = e.as<IndexExpr>();
            open("index", ix.bracket);
            expr(*ix.operand);
            expr(*ix.index);
            break;
        }
        case ExprKind::Image:
            open("image", e.span);
            expr(*e.as<ImageExpr>().path);
            break;
        default:  // Material, Checker, Perlin
            open(e.kind == ExprKind::Material  ? "material"
                 : e.kind == ExprKind::Checker ? "checker"
                                               : "perlin",
                 e.span);
            block(*e.as<BlockExpr>().block);
            break;
    }
    close();
}

void Printer::children(const std::string& label, Span at, ExprList items) {
    open(label, at);
    for (const Expr* item : items) expr(*item);
    close();
}

// Two operands as (binary OP a b) at the operator; a longer chain of one level flat, its operators
// between the operands: (chain a (op + ) b (op - ) c ...), at its start.
void Printer::binary(const BinaryExpr& e) {
    if (e.operands.size() == 2) {
        open(std::string("binary ") + binary_op_text(e.ops[0].op), e.ops[0].span);
        expr(*e.operands[0]);
        expr(*e.operands[1]);
        close();
        return;
    }
    open("chain", e.span);
    for (size_t i = 0; i < e.operands.size(); ++i) {
        if (i > 0) leaf(std::string("op ") + binary_op_text(e.ops[i - 1].op), e.ops[i - 1].span);
        expr(*e.operands[i]);
    }
    close();
}

// Each element as the generic parse would print it: `-1` is (unary - (number 1)).
void Printer::packed(const PackedListExpr& e) {
    open("packed_list", e.span);
    const PackedVectors& p = *e.packed;
    for (size_t i = 0; i < p.size(); ++i) {
        const PackedElementSpans spans = packed_element_spans(p, i, sources_);
        open("vector", spans.element);
        for (int c = 0; c < spans.count; ++c) {
            const double v = p.values[i * static_cast<size_t>(p.dims) + static_cast<size_t>(c)];
            const bool negated = spans.minus[c].end > spans.minus[c].begin;
            if (negated) open("unary -", spans.minus[c]);
            leaf("number " + format_number(negated ? -v : v), spans.number[c]);
            if (negated) close();
        }
        close();
    }
    close();
}

}  // namespace

std::string print_ast(const Program& program, const SourceManager& sources) {
    Printer printer(sources);
    for (const Stmt* s : program.statements) {
        printer.statement(*s);
        printer.out += '\n';
    }
    return printer.out;
}

}  // namespace wsd::lang
