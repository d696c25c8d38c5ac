// Modelica 3.x (the subset mocompile flattens), Optimica (JModelica's
// optimization classes and constraint sections), and the flat dialect that
// Scilab/Xcos writes (backquoted identifiers holding dots and brackets).
//
// The parse tree never leaves frontend/src: ast_builder.cpp turns it into
// mo::frontend::ast. Lexical errors are tokens of their own (UNTERMINATED_*,
// ERROR_CHAR) so that the front end reports them with a precise message.
grammar Modelica;

@parser::members {
/// One entry per enclosing class being parsed, true for an `optimization`
/// class. `constraint` opens a constraint section there; anywhere else it is
/// an ordinary identifier (the MSL names components so).
std::vector<bool> optimization_classes;
bool constraint_is_identifier() const {
  return optimization_classes.empty() || !optimization_classes.back();
}
}

stored_definition
    : (WITHIN name? ';')? (FINAL? class_definition ';')* EOF
    ;

class_definition
@init { std::size_t enclosing = optimization_classes.size(); }
    : ENCAPSULATED? class_prefixes
      { optimization_classes.push_back(_localctx->class_prefixes()->OPTIMIZATION() != nullptr); }
      class_specifier
    ;
    finally { optimization_classes.resize(enclosing); }

class_prefixes
    : PARTIAL?
      ( CLASS | MODEL | OPERATOR? RECORD | BLOCK | EXPANDABLE? CONNECTOR | TYPE
      | PACKAGE | (PURE | IMPURE)? OPERATOR? FUNCTION | OPERATOR | OPTIMIZATION )
    ;

class_specifier
    : long_class_specifier
    | short_class_specifier
    | der_class_specifier
    ;

long_class_specifier
    : IDENT class_modification? string_comment composition END IDENT
    | EXTENDS IDENT class_modification? string_comment composition END IDENT
    ;

short_class_specifier
    : IDENT '=' base_prefix type_specifier array_subscripts? class_modification? comment
    | IDENT '=' ENUMERATION '(' (enum_list? | ':') ')' comment
    ;

der_class_specifier
    : IDENT '=' DER '(' type_specifier ',' IDENT (',' IDENT)* ')' comment
    ;

base_prefix
    : (INPUT | OUTPUT)?
    ;

enum_list
    : enumeration_literal (',' enumeration_literal)*
    ;

enumeration_literal
    : IDENT comment
    ;

composition
    : element_list
      ( PUBLIC element_list
      | PROTECTED element_list
      | equation_section
      | algorithm_section
      | constraint_section
      )*
      ( EXTERNAL language_specification? external_function_call? annotation? ';' )?
      ( annotation ';' )?
    ;

language_specification
    : STRING
    ;

external_function_call
    : (component_reference '=')? IDENT '(' expression_list? ')'
    ;

element_list
    : (element ';' | annotation ';')*
    ;

element
    : import_clause
    | extends_clause
    | REDECLARE? FINAL? INNER? OUTER?
      ( class_definition
      | component_clause
      | REPLACEABLE (class_definition | component_clause) (constraining_clause comment)?
      )
    ;

import_clause
    : IMPORT ( IDENT '=' name | name ('.*' | '.' '*' | '.' '{' import_list '}')? ) comment
    ;

import_list
    : IDENT (',' IDENT)*
    ;

extends_clause
    : EXTENDS type_specifier class_modification? annotation?
    ;

constraining_clause
    : CONSTRAINEDBY type_specifier class_modification?
    ;

component_clause
    : type_prefix type_specifier array_subscripts? component_list
    ;

type_prefix
    : (FLOW | STREAM)? (DISCRETE | PARAMETER | CONSTANT)? (INPUT | OUTPUT)?
    ;

component_list
    : component_declaration (',' component_declaration)*
    ;

component_declaration
    : declaration condition_attribute? comment
    ;

condition_attribute
    : IF expression
    ;

declaration
    : (IDENT | {constraint_is_identifier()}? CONSTRAINT) array_subscripts? modification?
    ;

modification
    : class_modification ('=' expression)?
    | '=' expression
    | ':=' expression
    ;

class_modification
    : '(' argument_list? ')'
    ;

argument_list
    : argument (',' argument)*
    ;

argument
    : element_modification_or_replaceable
    | element_redeclaration
    ;

element_modification_or_replaceable
    : EACH? FINAL? (element_modification | element_replaceable)
    ;

element_modification
    : name modification? string_comment
    ;

element_redeclaration
    : REDECLARE EACH? FINAL?
      ( short_class_definition | component_clause1 | element_replaceable )
    ;

element_replaceable
    : REPLACEABLE (short_class_definition | component_clause1) constraining_clause?
    ;

component_clause1
    : type_prefix type_specifier component_declaration1
    ;

component_declaration1
    : declaration comment
    ;

short_class_definition
    : class_prefixes short_class_specifier
    ;

equation_section
    : INITIAL? EQUATION (equation ';' | annotation ';')*
    ;

algorithm_section
    : INITIAL? ALGORITHM (statement ';' | annotation ';')*
    ;

// Optimica: path and point constraints, `lhs = rhs`, `lhs <= rhs`, `lhs >= rhs`.
constraint_section
    : CONSTRAINT (constraint ';' | annotation ';')*
    ;

constraint
    : expression ('=' expression)? comment
    ;

equation
    : ( simple_expression '=' expression
      | if_equation
      | for_equation
      | connect_clause
      | when_equation
      | component_reference function_call_args
      ) comment
    ;

statement
    : ( component_reference (':=' expression | function_call_args)
      | '(' output_expression_list ')' ':=' component_reference function_call_args
      | BREAK
      | RETURN
      | if_statement
      | for_statement
      | while_statement
      | when_statement
      ) comment
    ;

if_equation
    : IF expression THEN (equation ';')*
      (ELSEIF expression THEN (equation ';')*)*
      (ELSE (equation ';')*)?
      END IF
    ;

if_statement
    : IF expression THEN (statement ';')*
      (ELSEIF expression THEN (statement ';')*)*
      (ELSE (statement ';')*)?
      END IF
    ;

for_equation
    : FOR for_indices LOOP (equation ';')* END FOR
    ;

for_statement
    : FOR for_indices LOOP (statement ';')* END FOR
    ;

for_indices
    : for_index (',' for_index)*
    ;

for_index
    : (IDENT | {constraint_is_identifier()}? CONSTRAINT) (IN expression)?
    ;

while_statement
    : WHILE expression LOOP (statement ';')* END WHILE
    ;

when_equation
    : WHEN expression THEN (equation ';')*
      (ELSEWHEN expression THEN (equation ';')*)*
      END WHEN
    ;

when_statement
    : WHEN expression THEN (statement ';')*
      (ELSEWHEN expression THEN (statement ';')*)*
      END WHEN
    ;

connect_clause
    : CONNECT '(' component_reference ',' component_reference ')'
    ;

expression
    : simple_expression                                                          # SimpleExpr
    | IF expression THEN expression (ELSEIF expression THEN expression)* ELSE expression  # IfExpr
    ;

simple_expression
    : logical_expression (':' logical_expression (':' logical_expression)?)?
    ;

logical_expression
    : logical_term (OR logical_term)*
    ;

logical_term
    : logical_factor (AND logical_factor)*
    ;

logical_factor
    : NOT? relation
    ;

relation
    : arithmetic_expression (relational_operator arithmetic_expression)?
    ;

relational_operator
    : '<' | '<=' | '>' | '>=' | '==' | '<>'
    ;

arithmetic_expression
    : add_operator? term (add_operator term)*
    ;

add_operator
    : '+' | '-' | '.+' | '.-'
    ;

term
    : factor (mul_operator factor)*
    ;

mul_operator
    : '*' | '/' | '.*' | './'
    ;

factor
    : primary (('^' | '.^') primary)?
    ;

primary
    : UNSIGNED_NUMBER                                          # NumberPrimary
    | STRING                                                   # StringPrimary
    | FALSE                                                    # FalsePrimary
    | TRUE                                                     # TruePrimary
    | (component_reference | DER | INITIAL | PURE) function_call_args  # CallPrimary
    | component_reference                                      # RefPrimary
    | '(' output_expression_list ')'                           # ParenPrimary
    | '[' expression_list (';' expression_list)* ']'           # MatrixPrimary
    | '{' array_arguments '}'                                  # ArrayPrimary
    | END                                                      # EndPrimary
    ;

type_specifier
    : '.'? name
    ;

name
    : IDENT ('.' IDENT)*
    ;

component_reference
    : '.'? (IDENT | {constraint_is_identifier()}? CONSTRAINT) array_subscripts?
      ('.' (IDENT | {constraint_is_identifier()}? CONSTRAINT) array_subscripts?)*
    ;

function_call_args
    : '(' function_arguments? ')'
    ;

function_arguments
    : expression (',' function_arguments_non_first | FOR for_indices)?
    | FUNCTION name '(' named_arguments? ')' (',' function_arguments_non_first)?
    | named_arguments
    ;

function_arguments_non_first
    : function_argument (',' function_arguments_non_first)?
    | named_arguments
    ;

array_arguments
    : expression ((',' expression)* | FOR for_indices)
    ;

named_arguments
    : named_argument (',' named_argument)*
    ;

named_argument
    : IDENT '=' function_argument
    ;

function_argument
    : FUNCTION name '(' named_arguments? ')'
    | expression
    ;

output_expression_list
    : expression? (',' expression?)*
    ;

expression_list
    : expression (',' expression)*
    ;

array_subscripts
    : '[' subscript (',' subscript)* ']'
    ;

subscript
    : ':'
    | expression
    ;

comment
    : string_comment annotation?
    ;

string_comment
    : (STRING ('+' STRING)*)?
    ;

annotation
    : ANNOTATION class_modification
    ;

// ---------------------------------------------------------------- lexer

ALGORITHM     : 'algorithm';
AND           : 'and';
ANNOTATION    : 'annotation';
BLOCK         : 'block';
BREAK         : 'break';
CLASS         : 'class';
CONNECT       : 'connect';
CONNECTOR     : 'connector';
CONSTANT      : 'constant';
CONSTRAINEDBY : 'constrainedby';
CONSTRAINT    : 'constraint';
DER           : 'der';
DISCRETE      : 'discrete';
EACH          : 'each';
ELSE          : 'else';
ELSEIF        : 'elseif';
ELSEWHEN      : 'elsewhen';
ENCAPSULATED  : 'encapsulated';
END           : 'end';
ENUMERATION   : 'enumeration';
EQUATION      : 'equation';
EXPANDABLE    : 'expandable';
EXTENDS       : 'extends';
EXTERNAL      : 'external';
FALSE         : 'false';
FINAL         : 'final';
FLOW          : 'flow';
FOR           : 'for';
FUNCTION      : 'function';
IF            : 'if';
IMPORT        : 'import';
IMPURE        : 'impure';
IN            : 'in';
INITIAL       : 'initial';
INNER         : 'inner';
INPUT         : 'input';
LOOP          : 'loop';
MODEL         : 'model';
NOT           : 'not';
OPERATOR      : 'operator';
OPTIMIZATION  : 'optimization';
OR            : 'or';
OUTER         : 'outer';
OUTPUT        : 'output';
PACKAGE       : 'package';
PARAMETER     : 'parameter';
PARTIAL       : 'partial';
PROTECTED     : 'protected';
PUBLIC        : 'public';
PURE          : 'pure';
RECORD        : 'record';
REDECLARE     : 'redeclare';
REPLACEABLE   : 'replaceable';
RETURN        : 'return';
STREAM        : 'stream';
THEN          : 'then';
TRUE          : 'true';
TYPE          : 'type';
WHEN          : 'when';
WHILE         : 'while';
WITHIN        : 'within';

IDENT
    : NONDIGIT (DIGIT | NONDIGIT)*
    | Q_IDENT
    | B_IDENT
    ;

fragment Q_IDENT  : '\'' (Q_CHAR | S_ESCAPE)+ '\'';
// Xcos' flat dialect: `Capacitor1.v`, `n_12.[2]` — anything but a backquote or newline.
fragment B_IDENT  : '`' ~[`\r\n]+ '`';
fragment NONDIGIT : [a-zA-Z_];
fragment DIGIT    : [0-9];
fragment Q_CHAR   : ~['\\\r\n];
fragment S_ESCAPE : '\\' ['"?\\abfnrtv];

STRING : '"' (~["\\] | '\\' .)* '"';

UNSIGNED_NUMBER
    : DIGIT+ ('.' DIGIT*)? EXPONENT?
    | '.' DIGIT+ EXPONENT?
    ;
fragment EXPONENT : [eE] [+-]? DIGIT+;

// Error tokens: each one is the longest match only when its well-formed
// counterpart cannot match, so the front end can name the mistake.
UNTERMINATED_STRING : '"' (~["\\] | '\\' .)*;
UNTERMINATED_QIDENT : '\'' (Q_CHAR | S_ESCAPE)*;
UNTERMINATED_BIDENT : '`' ~[`\r\n]*;

WS            : [ \t\r\n\f]+ -> channel(HIDDEN);
LINE_COMMENT  : '//' ~[\r\n]* -> channel(HIDDEN);
BLOCK_COMMENT : '/*' .*? '*/' -> channel(HIDDEN);
UNTERMINATED_COMMENT : '/*' (~'*' | '*'+ ~[*/])* '*'* EOF;

ERROR_CHAR : .;
