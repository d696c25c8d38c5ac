#include "mo/frontend/parser.hpp"

#include "ModelicaLexer.h"
#include "ModelicaParser.h"
#include "ast_builder.hpp"

#include <fmt/format.h>
#include <pthread.h>

#include <functional>

namespace mo::frontend {

namespace g = mo::frontend::grammar;

namespace {

/// An ANTLR char stream over raw bytes: each byte is one "character", so
/// token indices are byte offsets and invalid UTF-8 cannot throw. Non-ASCII
/// bytes only ever occur inside strings and comments of a valid file. A
/// UTF-8 byte-order mark at the start reads as blanks (offsets unchanged).
class ByteStream : public antlr4::ANTLRInputStream {
public:
  explicit ByteStream(std::string_view text) {
    _data.reserve(text.size());
    const std::size_t bom = text.starts_with("\xEF\xBB\xBF") ? 3 : 0;
    for (std::size_t i = 0; i < text.size(); ++i)
      _data.push_back(i < bom ? U' ' : static_cast<char32_t>(static_cast<unsigned char>(text[i])));
    p = 0;
  }
};

/// Turns ANTLR's syntax errors into our diagnostics, with short messages.
class SyntaxErrorListener : public antlr4::BaseErrorListener {
public:
  SyntaxErrorListener(FileId file, std::string_view text, DiagnosticEngine &diags)
      : file_(file), text_(text), diags_(diags) {}

  void syntaxError(antlr4::Recognizer *recognizer, antlr4::Token *offending, size_t, size_t,
                   const std::string &, std::exception_ptr) override {
    ++count_;
    SourceRange r{file_, static_cast<std::uint32_t>(text_.size()),
                  static_cast<std::uint32_t>(text_.size())};
    std::string what = "end of file";
    if (offending && offending->getType() != antlr4::Token::EOF) {
      r.begin = static_cast<std::uint32_t>(offending->getStartIndex());
      r.end = static_cast<std::uint32_t>(offending->getStopIndex() + 1);
      what = "'" + std::string(text_.substr(r.begin, std::min<std::uint32_t>(r.end - r.begin, 40))) + "'";
    }
    std::string msg = "unexpected " + what;
    if (auto *parser = dynamic_cast<antlr4::Parser *>(recognizer)) {
      std::string expected = expected_text(*parser);
      if (!expected.empty())
        msg += "; expected " + expected;
    }
    diags_.report(DiagId::SyntaxError, r, msg);
  }

  unsigned count() const { return count_; }

private:
  FileId file_;
  std::string_view text_;
  DiagnosticEngine &diags_;
  unsigned count_ = 0;

  /// "';'", "';' or ')'", or "" when too many tokens would fit to be useful.
  static std::string expected_text(antlr4::Parser &parser) {
    antlr4::misc::IntervalSet set;
    try {
      set = parser.getExpectedTokens();
    } catch (...) {
      return "";
    }
    std::vector<std::string> names;
    for (auto t : set.toList()) {
      if (t == static_cast<ssize_t>(g::ModelicaParser::CONSTRAINT) &&
          set.contains(static_cast<ssize_t>(g::ModelicaParser::IDENT)))
        continue; // `constraint` is then just one more identifier
      if (t == static_cast<ssize_t>(antlr4::Token::EOF)) {
        names.push_back("end of file");
        continue;
      }
      std::string n = parser.getVocabulary().getDisplayName(t);
      if (n == "IDENT") n = "an identifier";
      else if (n == "UNSIGNED_NUMBER") n = "a number";
      else if (n == "STRING") n = "a string";
      else if (n.size() <= 1 || n.front() != '\'') { // a token name, not a literal like ';'
        for (auto &c : n) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        n = "'" + n + "'";
      }
      names.push_back(n);
    }
    if (names.empty() || names.size() > 4)
      return "";
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
      out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
  }
};

/// True for the binary operators that chain operands into a left-deep
/// expression tree (`a - b - c` is ((a - b) - c)): each one adds a level to
/// the AST. `after_operand`: the previous token ends an operand, so '+' and
/// '-' are binary (a leading sign is not a chain; the grammar allows one).
bool is_chaining_operator(std::string_view s, std::size_t type, bool after_operand) {
  if (s == "+" || s == "-" || s == ".+" || s == ".-") return after_operand;
  return s == "*" || s == "/" || s == ".*" || s == "./" || type == g::ModelicaLexer::AND ||
         type == g::ModelicaLexer::OR;
}

/// True if the token can end an operand (a name, a literal, a closing bracket).
bool ends_operand(std::string_view s, std::size_t type) {
  return type == g::ModelicaLexer::IDENT || type == g::ModelicaLexer::UNSIGNED_NUMBER ||
         type == g::ModelicaLexer::STRING || type == g::ModelicaLexer::TRUE ||
         type == g::ModelicaLexer::FALSE || type == g::ModelicaLexer::END || s == ")" || s == "]" ||
         s == "}";
}

/// Bounds the depth of the expression trees a statement can build: brackets
/// and if-expressions nest, and each chaining operator in the current list
/// element adds a level (a 20 000-term sum is 20 000 levels deep). Counts are
/// kept per bracket level and restart at ',' and ';', so long lists and many
/// statements are free.
class NestingCounter {
public:
  void open() { chains_.push_back(0); }
  void close() {
    if (!chains_.empty()) chains_.pop_back();
  }
  void next_element() {
    if (!chains_.empty()) chains_.back() = 0; else top_ = 0;
  }
  void next_statement() { chains_.clear(), top_ = 0; }
  void chain() { ++(chains_.empty() ? top_ : chains_.back()); }
  /// Upper bound of the tree depth so far (brackets + operator chains).
  std::size_t depth() const {
    std::size_t d = top_ + chains_.size();
    for (unsigned c : chains_) d += c;
    return d;
  }

private:
  std::vector<unsigned> chains_; ///< chaining operators per open bracket
  unsigned top_ = 0;             ///< chaining operators outside brackets
};

/// Reports lexical error tokens and over-deep nesting. Returns false when the
/// token stream must not be parsed.
bool check_tokens(const std::vector<antlr4::Token *> &tokens, FileId file, std::string_view text,
                  DiagnosticEngine &diags, const ParseOptions &options) {
  bool ok = true;
  unsigned ifs = 0;
  NestingCounter nesting;
  bool after_operand = false;
  for (antlr4::Token *t : tokens) {
    SourceRange r{file, static_cast<std::uint32_t>(t->getStartIndex()),
                  static_cast<std::uint32_t>(t->getStopIndex() + 1)};
    switch (t->getType()) {
    case g::ModelicaLexer::UNTERMINATED_STRING:
      diags.report(DiagId::UnterminatedString, {file, r.begin, r.begin + 1},
                   "unterminated string literal");
      ok = false;
      break;
    case g::ModelicaLexer::UNTERMINATED_QIDENT:
    case g::ModelicaLexer::UNTERMINATED_BIDENT:
      diags.report(DiagId::UnterminatedQuotedIdent, {file, r.begin, r.begin + 1},
                   std::string("unterminated quoted identifier (missing closing ") +
                       (text[r.begin] == '`' ? "'`'" : "\"'\"") + " on this line)");
      ok = false;
      break;
    case g::ModelicaLexer::UNTERMINATED_COMMENT:
      diags.report(DiagId::UnterminatedComment, {file, r.begin, r.begin + 2},
                   "unterminated /* comment");
      ok = false;
      break;
    case g::ModelicaLexer::ERROR_CHAR: {
      unsigned char c = static_cast<unsigned char>(text[r.begin]);
      std::string shown = (c >= 0x20 && c < 0x7f) ? std::string("'") + static_cast<char>(c) + "'"
                                                 : fmt::format("byte 0x{:02x}", c);
      diags.report(c >= 0x80 ? DiagId::InvalidEncoding : DiagId::InvalidCharacter, r,
                   "invalid character " + shown + " in Modelica text");
      ok = false;
      break;
    }
    case g::ModelicaLexer::IF:
      ++ifs;
      break;
    default: {
      std::string_view s = text.substr(r.begin, r.end - r.begin);
      if (s == "(" || s == "[" || s == "{") {
        nesting.open();
      } else if (s == ")" || s == "]" || s == "}") {
        nesting.close();
      } else if (s == ",") {
        nesting.next_element();
      } else if (s == ";") {
        ifs = 0;
        nesting.next_statement();
      } else if (is_chaining_operator(s, t->getType(), after_operand)) {
        nesting.chain();
      }
    }
    }
    if (t->getChannel() == antlr4::Token::DEFAULT_CHANNEL) // whitespace and comments are hidden
      after_operand = ends_operand(text.substr(r.begin, r.end - r.begin), t->getType());
    if (nesting.depth() + ifs > options.max_nesting) {
      diags.report(DiagId::NestingTooDeep, r,
                   fmt::format("expression nested more than {} levels deep", options.max_nesting));
      return false;
    }
  }
  return ok;
}

/// Runs `fn` on a thread with a large stack: ANTLR's recursive descent uses
/// several frames per nesting level (more under sanitizers).
void run_with_large_stack(const std::function<void()> &fn) {
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, std::size_t(512) << 20);
  struct Payload {
    const std::function<void()> *fn;
    std::exception_ptr error;
  } payload{&fn, nullptr};
  pthread_t thread;
  auto entry = [](void *arg) -> void * {
    auto *p = static_cast<Payload *>(arg);
    try {
      (*p->fn)();
    } catch (...) {
      p->error = std::current_exception();
    }
    return nullptr;
  };
  if (pthread_create(&thread, &attr, entry, &payload) != 0) {
    pthread_attr_destroy(&attr);
    fn(); // no thread available: run here
    return;
  }
  pthread_join(thread, nullptr);
  pthread_attr_destroy(&attr);
  if (payload.error)
    std::rethrow_exception(payload.error);
}

std::unique_ptr<ast::StoredDefinition> parse_here(FileId file, const SourceManager &sources,
                                                  DiagnosticEngine &diags,
                                                  const ParseOptions &options) {
  std::string_view text = sources.text(file);
  bool blank = true;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) blank = false;
  if (blank) {
    diags.report(DiagId::EmptyFile, {file, 0, 0}, "file is empty: expected a class definition");
    return nullptr;
  }

  ByteStream input(text);
  g::ModelicaLexer lexer(&input);
  lexer.removeErrorListeners(); // every lexical error is an error token
  antlr4::CommonTokenStream tokens(&lexer);
  tokens.fill();
  if (!check_tokens(tokens.getTokens(), file, text, diags, options))
    return nullptr;

  g::ModelicaParser parser(&tokens);
  parser.removeErrorListeners();
  SyntaxErrorListener listener(file, text, diags);
  parser.addErrorListener(&listener);
  // Two-stage parsing: fast SLL prediction, full LL only if SLL fails.
  parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
      antlr4::atn::PredictionMode::SLL);
  parser.setErrorHandler(std::make_shared<antlr4::BailErrorStrategy>());
  g::ModelicaParser::Stored_definitionContext *tree = nullptr;
  try {
    tree = parser.stored_definition();
  } catch (const antlr4::ParseCancellationException &) {
    tokens.seek(0);
    parser.reset();
    parser.optimization_classes.clear();
    parser.setErrorHandler(std::make_shared<antlr4::DefaultErrorStrategy>());
    parser.getInterpreter<antlr4::atn::ParserATNSimulator>()->setPredictionMode(
        antlr4::atn::PredictionMode::LL);
    tree = parser.stored_definition();
  }
  if (listener.count() > 0)
    return nullptr;
  unsigned before = diags.error_count();
  auto sd = detail::AstBuilder(file, text, diags).build(tree);
  if (diags.error_count() > before)
    return nullptr;
  return sd;
}

} // namespace

std::unique_ptr<ast::StoredDefinition> parse(FileId file, const SourceManager &sources,
                                             DiagnosticEngine &diags,
                                             const ParseOptions &options) {
  std::unique_ptr<ast::StoredDefinition> result;
  run_with_large_stack([&] { result = parse_here(file, sources, diags, options); });
  return result;
}

std::unique_ptr<ast::StoredDefinition> parse_file(const std::string &path, SourceManager &sources,
                                                  DiagnosticEngine &diags,
                                                  const ParseOptions &options) {
  std::string error;
  FileId file = sources.load(path, error);
  if (file == 0) {
    diags.report(DiagId::CannotReadFile, {}, error);
    return nullptr;
  }
  return parse(file, sources, diags, options);
}

} // namespace mo::frontend
