// Arithmetic over axis names for coupled axes (`delta = "-1.5*alpha"`, the paper's eq. 19):
// numbers (`2`, `0.25`, `1e-3`), names ([a-z_][a-z0-9_]*), binary + − * /, unary minus and
// parentheses, with the usual precedence (* and / bind tighter than + and −, all left
// associative). There are no powers and no functions: a coupled axis is meant to be a line or
// a simple relation, and anything more belongs in a list study.
//
// Thread safety: an AxisExpression is immutable after parse(), so it may be evaluated from any
// number of threads at once (the lookup function must be safe to call the same way).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace impactid {

class AxisExpression {
 public:
  /// Parses `text`; on failure returns nothing and sets `error` to a message that starts with
  /// the 1-based column of the offending character ("column 6: expected a number, a name or
  /// '(' but found the end").
  static std::optional<AxisExpression> parse(const std::string& text, std::string& error);

  /// The names the expression uses, each once, in order of first appearance.
  const std::vector<std::string>& variables() const { return variables_; }
  /// Evaluates with `lookup` giving each variable's value. IEEE arithmetic throughout: a
  /// division by zero gives ±inf or NaN, which the settings' range checks then reject by name.
  double evaluate(const std::function<double(const std::string&)>& lookup) const;
  /// The text as given to parse().
  const std::string& text() const { return text_; }

  struct Node;

 private:
  std::string text_;
  std::vector<std::string> variables_;
  std::shared_ptr<const Node> root_;  // immutable, so copies may share it
};

}  // namespace impactid
