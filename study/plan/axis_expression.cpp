#include "study/plan/axis_expression.hpp"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string_view>

namespace impactid {

struct AxisExpression::Node {
  enum class Kind { number, variable, negate, add, subtract, multiply, divide };
  Kind kind = Kind::number;
  double number = 0.0;
  std::string name;                         // variable
  std::shared_ptr<const Node> left, right;  // operands; negate uses left only
};

namespace {

using Node = AxisExpression::Node;
using NodePtr = std::shared_ptr<const Node>;

// Thrown inside the parser only; parse() turns it into the `error` text.
struct SyntaxError {
  std::size_t column;  // 1-based
  std::string what;
};

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_name_start(char c) {
  return (c >= 'a' && c <= 'z') || c == '_';
}
bool is_name_char(char c) {
  return is_name_start(c) || is_digit(c);
}

// expression := term (('+' | '-') term)*
// term       := unary (('*' | '/') unary)*
// unary      := '-' unary | primary
// primary    := number | name | '(' expression ')'
class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {}

  NodePtr parse_all() {
    skip_space();
    if (at_end()) throw SyntaxError{column(), "the expression is empty"};
    NodePtr root = expression();
    skip_space();
    if (!at_end()) {
      if (peek() == ')') throw SyntaxError{column(), "unmatched ')'"};
      throw SyntaxError{column(),
                        "expected an operator (+ - * /) or the end but found " + describe_here()};
    }
    return root;
  }

  std::vector<std::string> variables() const { return variables_; }

 private:
  NodePtr expression() {
    NodePtr left = term();
    for (skip_space(); !at_end() && (peek() == '+' || peek() == '-'); skip_space()) {
      const Node::Kind kind = peek() == '+' ? Node::Kind::add : Node::Kind::subtract;
      ++pos_;
      left = binary(kind, left, term());
    }
    return left;
  }

  NodePtr term() {
    NodePtr left = unary();
    for (skip_space(); !at_end() && (peek() == '*' || peek() == '/'); skip_space()) {
      const Node::Kind kind = peek() == '*' ? Node::Kind::multiply : Node::Kind::divide;
      ++pos_;
      left = binary(kind, left, unary());
    }
    return left;
  }

  NodePtr unary() {
    skip_space();
    // Nesting deeper than this is not an axis relation; the limit keeps the recursion bounded.
    if (++depth_ > kMaxDepth) throw SyntaxError{column(), "the expression nests too deeply"};
    struct Leave {
      int& depth;
      ~Leave() { --depth; }
    } leave{depth_};
    if (!at_end() && peek() == '-') {
      ++pos_;
      auto node = std::make_shared<Node>();
      node->kind = Node::Kind::negate;
      node->left = unary();
      return node;
    }
    return primary();
  }

  NodePtr primary() {
    skip_space();
    if (at_end()) throw SyntaxError{column(), "expected a number, a name or '(' but found the end"};
    const char c = peek();
    if (c == '(') {
      const std::size_t open = column();
      ++pos_;
      NodePtr inner = expression();
      skip_space();
      if (at_end()) throw SyntaxError{open, "'(' is never closed"};
      if (peek() != ')') {
        throw SyntaxError{column(), "expected ')' or an operator but found " + describe_here()};
      }
      ++pos_;
      return inner;
    }
    if (is_digit(c) || c == '.') return number();
    if (is_name_start(c)) return variable();
    throw SyntaxError{column(), "expected a number, a name or '(' but found " + describe_here()};
  }

  // digits ['.' digits] | '.' digits, then an optional exponent e[+-]digits.
  NodePtr number() {
    const std::size_t start = pos_;
    const auto digits = [&] {
      const std::size_t from = pos_;
      while (!at_end() && is_digit(peek())) ++pos_;
      return pos_ - from;
    };
    std::size_t mantissa = digits();
    if (!at_end() && peek() == '.') {
      ++pos_;
      mantissa += digits();
    }
    if (mantissa == 0) throw SyntaxError{start + 1, "a number needs a digit"};
    if (!at_end() && (peek() == 'e' || peek() == 'E')) {
      ++pos_;
      if (!at_end() && (peek() == '+' || peek() == '-')) ++pos_;
      if (digits() == 0) throw SyntaxError{column(), "the exponent of a number needs a digit"};
    }
    if (!at_end() && (is_name_char(peek()) || peek() == '.')) {
      throw SyntaxError{column(), "unexpected " + describe_here() + " after a number"};
    }
    auto node = std::make_shared<Node>();
    node->kind = Node::Kind::number;
    const std::string_view lexeme = text_.substr(start, pos_ - start);
    const auto [end, ec] =
        std::from_chars(lexeme.data(), lexeme.data() + lexeme.size(), node->number);
    if (ec == std::errc::result_out_of_range) {
      throw SyntaxError{start + 1, "the number " + std::string(lexeme) + " is out of range"};
    }
    // The lexer only lets through what from_chars reads in full.
    assert(ec == std::errc() && end == lexeme.data() + lexeme.size());
    return node;
  }

  NodePtr variable() {
    const std::size_t start = pos_;
    while (!at_end() && is_name_char(peek())) ++pos_;
    if (!at_end() && peek() >= 'A' && peek() <= 'Z') {
      throw SyntaxError{column(), "unexpected " + describe_here()};
    }
    auto node = std::make_shared<Node>();
    node->kind = Node::Kind::variable;
    node->name = std::string(text_.substr(start, pos_ - start));
    if (std::find(variables_.begin(), variables_.end(), node->name) == variables_.end()) {
      variables_.push_back(node->name);
    }
    return node;
  }

  static NodePtr binary(Node::Kind kind, NodePtr left, NodePtr right) {
    auto node = std::make_shared<Node>();
    node->kind = kind;
    node->left = std::move(left);
    node->right = std::move(right);
    return node;
  }

  std::string describe_here() const {
    const char c = peek();
    if (c == '^') return "'^' (powers are not supported)";
    if (c >= 'A' && c <= 'Z') return std::string("'") + c + "' (names are lower case)";
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) {
      return "a character that is not ASCII or not printable";
    }
    return std::string("'") + c + "'";
  }

  void skip_space() {
    while (!at_end() && (peek() == ' ' || peek() == '\t')) ++pos_;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }
  // Columns count bytes: expressions are ASCII, and the first non-ASCII byte is an error.
  std::size_t column() const { return pos_ + 1; }

  std::string_view text_;
  std::size_t pos_ = 0;
  int depth_ = 0;
  static constexpr int kMaxDepth = 200;
  std::vector<std::string> variables_;
};

double evaluate_node(const Node& node, const std::function<double(const std::string&)>& lookup) {
  switch (node.kind) {
    case Node::Kind::number:
      return node.number;
    case Node::Kind::variable:
      return lookup(node.name);
    case Node::Kind::negate:
      return -evaluate_node(*node.left, lookup);
    case Node::Kind::add:
      return evaluate_node(*node.left, lookup) + evaluate_node(*node.right, lookup);
    case Node::Kind::subtract:
      return evaluate_node(*node.left, lookup) - evaluate_node(*node.right, lookup);
    case Node::Kind::multiply:
      return evaluate_node(*node.left, lookup) * evaluate_node(*node.right, lookup);
    case Node::Kind::divide:
      return evaluate_node(*node.left, lookup) / evaluate_node(*node.right, lookup);
  }
  assert(false && "unhandled AxisExpression node");
  return 0.0;
}

}  // namespace

std::optional<AxisExpression> AxisExpression::parse(const std::string& text, std::string& error) {
  Parser parser(text);
  try {
    AxisExpression out;
    out.root_ = parser.parse_all();
    out.text_ = text;
    out.variables_ = parser.variables();
    error.clear();
    return out;
  } catch (const SyntaxError& e) {
    error = "column " + std::to_string(e.column) + ": " + e.what;
    return std::nullopt;
  }
}

double AxisExpression::evaluate(const std::function<double(const std::string&)>& lookup) const {
  assert(root_ && "evaluate() on an AxisExpression that parse() did not produce");
  return evaluate_node(*root_, lookup);
}

}  // namespace impactid
