// Arithmetic over axis names for coupled axes: numbers, names, + − * /, unary minus and
// parentheses ("-1.5*alpha", "0.25*(1 - alpha)^..." is not supported: no powers).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace impactid {

class AxisExpression {
 public:
  /// Parses `text`; on failure returns nothing and sets `error` to a message with the column.
  static std::optional<AxisExpression> parse(const std::string& text, std::string& error);

  /// The names the expression uses.
  const std::vector<std::string>& variables() const { return variables_; }
  /// Evaluates with `lookup` giving each variable's value.
  double evaluate(const std::function<double(const std::string&)>& lookup) const;
  const std::string& text() const { return text_; }

  struct Node;

 private:
  std::string text_;
  std::vector<std::string> variables_;
  std::shared_ptr<const Node> root_;  // immutable, so copies may share it
};

}  // namespace impactid
