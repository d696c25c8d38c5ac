#pragma once
// Converts the ANTLR parse tree into our AST. Internal to the frontend.
#include "ModelicaParser.h"
#include "mo/frontend/ast.hpp"
#include "mo/frontend/diagnostics.hpp"

namespace mo::frontend::detail {

namespace g = mo::frontend::grammar;

/// Builds ast nodes from a parse tree that has no syntax errors.
/// Appends the equations that algorithm `section` of a model means when its
/// statements are assignments (and when-statements and assert/terminate/
/// reinit calls of such), each variable assigned by one statement and not
/// read by an earlier one (algorithm_equations.cpp); false, and nothing
/// changed, for any other section.
bool algorithm_as_equations(std::vector<ast::Statement> &section, std::vector<ast::Equation> &out);

class AstBuilder {
public:
  AstBuilder(FileId file, std::string_view text, DiagnosticEngine &diags)
      : file_(file), text_(text), diags_(diags) {}

  std::unique_ptr<ast::StoredDefinition> build(g::ModelicaParser::Stored_definitionContext *ctx);

private:
  using P = g::ModelicaParser;
  FileId file_;
  std::string_view text_;
  DiagnosticEngine &diags_;
  unsigned class_depth_ = 0;
  static constexpr unsigned kMaxClassDepth = 100;

  SourceRange range(antlr4::Token *t) const;
  SourceRange range(antlr4::ParserRuleContext *ctx) const;
  SourceRange range(antlr4::tree::TerminalNode *n) const { return range(n->getSymbol()); }
  std::string text(antlr4::Token *t) const;
  std::string ident(antlr4::tree::TerminalNode *n) const;

  ast::ClassPtr class_definition(P::Class_definitionContext *ctx);
  void composition(P::CompositionContext *ctx, ast::ClassDef &cls);
  void element_list(P::Element_listContext *ctx, ast::ClassDef &cls, bool is_protected);
  void vendor_annotation(P::AnnotationContext *ctx, ast::ClassDef &cls);
  void element(P::ElementContext *ctx, ast::ClassDef &cls, bool is_protected);
  void component_clause(P::Component_clauseContext *ctx, ast::ClassDef &cls, bool is_protected,
                        P::ElementContext *prefixes);
  ast::Import import_clause(P::Import_clauseContext *ctx);
  ast::TypeName type_specifier(P::Type_specifierContext *ctx);
  std::vector<std::string> name(P::NameContext *ctx);
  ast::Modification modification(P::ModificationContext *ctx);
  ast::Modification class_modification(P::Class_modificationContext *ctx);
  ast::ElementMod argument(P::ArgumentContext *ctx);
  /// `replaceable T x(...) constrainedby C(...)` or `replaceable model M = T` in a modifier.
  void redeclaration(P::Element_replaceableContext *ctx, ast::ElementMod &em);
  std::unique_ptr<ast::Component> component_clause1(P::Component_clause1Context *ctx);
  /// The component `d` declares, with its type prefixes, type, dimensions and modification.
  ast::Component declaration(P::Type_prefixContext *tp, const ast::TypeName &type, P::DeclarationContext *d,
                             P::Array_subscriptsContext *type_dims);
  void short_class(P::Short_class_specifierContext *sc, ast::ClassDef &cls);
  ast::ClassPtr short_class_definition(P::Short_class_definitionContext *ctx);
  std::string string_comment(P::String_commentContext *ctx);
  std::string comment(P::CommentContext *ctx);
  /// True for `annotation(..., Evaluate = true, ...)` in a declaration's comment.
  bool evaluate_annotation(P::CommentContext *ctx);

  ast::Equation equation(P::EquationContext *ctx);
  ast::Equation constraint(P::ConstraintContext *ctx);
  // statements (ast_builder_statements.cpp)
  ast::Statement statement(P::StatementContext *ctx);
  std::vector<ast::Statement> statements(const std::vector<P::StatementContext *> &list);
  void external_clause(P::CompositionContext *ctx, ast::ClassDef &cls);
  std::vector<ast::ForIndex> for_indices(P::For_indicesContext *ctx);

  ast::ExprPtr expression(P::ExpressionContext *ctx);
  ast::ExprPtr simple_expression(P::Simple_expressionContext *ctx);
  ast::ExprPtr logical_expression(P::Logical_expressionContext *ctx);
  ast::ExprPtr logical_term(P::Logical_termContext *ctx);
  ast::ExprPtr logical_factor(P::Logical_factorContext *ctx);
  ast::ExprPtr relation(P::RelationContext *ctx);
  ast::ExprPtr arithmetic_expression(P::Arithmetic_expressionContext *ctx);
  ast::ExprPtr term(P::TermContext *ctx);
  ast::ExprPtr factor(P::FactorContext *ctx);
  ast::ExprPtr primary(P::PrimaryContext *ctx);
  ast::ExprPtr number(antlr4::tree::TerminalNode *n);
  ast::ExprPtr call(P::CallPrimaryContext *ctx);
  void function_arguments(P::Function_argumentsContext *ctx, ast::Expr &call);
  void function_arguments_non_first(P::Function_arguments_non_firstContext *ctx, ast::Expr &call);
  void named_arguments(P::Named_argumentsContext *ctx, ast::Expr &call);
  ast::ExprPtr function_argument(P::Function_argumentContext *ctx);
  ast::ComponentRef component_reference(P::Component_referenceContext *ctx);
  std::vector<ast::ExprPtr> array_subscripts(P::Array_subscriptsContext *ctx);
  ast::ExprPtr ref_expr(P::Component_referenceContext *ctx);
};

} // namespace mo::frontend::detail
