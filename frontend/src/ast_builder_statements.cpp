// Algorithm statements and the external clause of functions → AST.
#include "ast_builder.hpp"

namespace mo::frontend::detail {

using namespace ast;

std::vector<Statement> AstBuilder::statements(const std::vector<P::StatementContext *> &list) {
  std::vector<Statement> out;
  for (auto *st : list)
    out.push_back(statement(st));
  return out;
}

namespace {

/// Splits the children of an if/when statement into branches: a branch
/// starts at IF/ELSEIF/ELSE (or WHEN/ELSEWHEN) and holds the statements after it.
template <class Ctx, class Builder>
std::vector<StatementBranch> branches(Ctx *ctx, std::size_t opener, std::size_t next_opener,
                                      std::size_t else_token, Builder &&build) {
  std::vector<StatementBranch> out;
  std::size_t cond_index = 0;
  auto conds = ctx->expression();
  for (auto *child : ctx->children) {
    if (auto *t = dynamic_cast<antlr4::tree::TerminalNode *>(child)) {
      auto type = t->getSymbol()->getType();
      if ((type == opener && out.empty()) || type == next_opener)
        out.push_back(StatementBranch{build.expr(conds[cond_index++]), {}, build.range(t)});
      else if (type == else_token && else_token != 0)
        out.push_back(StatementBranch{nullptr, {}, build.range(t)});
    } else if (auto *st = dynamic_cast<grammar::ModelicaParser::StatementContext *>(child)) {
      out.back().body.push_back(build.statement(st));
    }
  }
  return out;
}

} // namespace

Statement AstBuilder::statement(P::StatementContext *ctx) {
  Statement st;
  st.range = range(ctx);
  struct Build {
    AstBuilder &b;
    ExprPtr expr(P::ExpressionContext *e) { return b.expression(e); }
    SourceRange range(antlr4::tree::TerminalNode *t) { return b.range(t); }
    Statement statement(P::StatementContext *s) { return b.statement(s); }
  } build{*this};
  if (auto *i = ctx->if_statement()) {
    st.kind = StatementKind::If;
    st.branches = branches(i, P::IF, P::ELSEIF, P::ELSE, build);
  } else if (auto *w = ctx->when_statement()) {
    st.kind = StatementKind::When;
    st.branches = branches(w, P::WHEN, P::ELSEWHEN, 0, build);
  } else if (auto *f = ctx->for_statement()) {
    st.kind = StatementKind::For;
    st.indices = for_indices(f->for_indices());
    st.body = statements(f->statement());
  } else if (auto *wh = ctx->while_statement()) {
    st.kind = StatementKind::While;
    st.value = expression(wh->expression());
    st.body = statements(wh->statement());
  } else if (ctx->BREAK()) {
    st.kind = StatementKind::Break;
  } else if (ctx->RETURN()) {
    st.kind = StatementKind::Return;
  } else if (ctx->function_call_args()) {
    // `f(args);` or `(a, b) := f(args);`: the call is built as an expression.
    auto callee = std::make_unique<Expr>(ExprKind::Call, range(ctx->component_reference()));
    callee->ref = component_reference(ctx->component_reference());
    if (auto *args = ctx->function_call_args()->function_arguments())
      function_arguments(args, *callee);
    callee->range.end = range(ctx->function_call_args()).end;
    st.value = std::move(callee);
    st.kind = StatementKind::Call;
    if (auto *list = ctx->output_expression_list()) {
      st.kind = StatementKind::Assign;
      bool pending = true;
      for (auto *child : list->children) {
        if (auto *ex = dynamic_cast<P::ExpressionContext *>(child)) {
          st.targets.push_back(expression(ex));
          pending = false;
        } else {
          if (pending)
            st.targets.push_back(nullptr);
          pending = true;
        }
      }
      if (pending && !list->children.empty())
        st.targets.push_back(nullptr);
    }
  } else {
    st.kind = StatementKind::Assign;
    st.targets.push_back(ref_expr(ctx->component_reference()));
    st.value = expression(ctx->expression());
  }
  return st;
}

void AstBuilder::external_clause(P::CompositionContext *ctx, ClassDef &cls) {
  if (auto *lang = ctx->language_specification()) {
    std::string raw = text(lang->STRING()->getSymbol());
    cls.external_language = unescape_string(raw.substr(1, raw.size() - 2));
  }
  if (auto *call = ctx->external_function_call()) {
    cls.external_function = ident(call->IDENT());
    if (auto *result = call->component_reference())
      cls.external_result = component_reference(result).str();
    if (auto *list = call->expression_list())
      for (auto *x : list->expression())
        cls.external_args.push_back(expression(x));
  }
}

} // namespace mo::frontend::detail
