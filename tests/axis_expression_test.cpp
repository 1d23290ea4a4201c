// Coupled-axis expressions: the values they compute (precedence, associativity, number forms)
// and the column their syntax errors point at.
#include "study/plan/axis_expression.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

namespace impactid {
namespace {

// Parses or fails the test; evaluates with the given variable values.
double value_of(const std::string& text, const std::map<std::string, double>& vars = {}) {
  std::string error;
  const auto e = AxisExpression::parse(text, error);
  if (!e) {
    ADD_FAILURE() << "'" << text << "' did not parse: " << error;
    return std::nan("");
  }
  EXPECT_EQ(error, "");
  return e->evaluate([&](const std::string& name) {
    const auto it = vars.find(name);
    if (it == vars.end()) {
      ADD_FAILURE() << "lookup of unexpected name '" << name << "'";
      return std::nan("");
    }
    return it->second;
  });
}

std::string error_of(const std::string& text) {
  std::string error;
  const auto e = AxisExpression::parse(text, error);
  EXPECT_FALSE(e.has_value()) << "'" << text << "' parsed";
  return error;
}

TEST(AxisExpression, EquationNineteenGivesDeltaFromAlpha) {
  // δ = −1.5α (eq. 19): exact for these binary-representable α.
  EXPECT_EQ(value_of("-1.5*alpha", {{"alpha", -0.5}}), 0.75);
  EXPECT_EQ(value_of("-1.5*alpha", {{"alpha", -0.25}}), 0.375);
  EXPECT_EQ(value_of("-1.5*alpha", {{"alpha", 0.0}}), 0.0);
  EXPECT_EQ(value_of("-1.5 * alpha", {{"alpha", -0.3}}), -1.5 * -0.3);
}

TEST(AxisExpression, PrecedenceAndAssociativity) {
  EXPECT_EQ(value_of("1 + 2*3"), 7.0);
  EXPECT_EQ(value_of("(1 + 2)*3"), 9.0);
  EXPECT_EQ(value_of("8/4/2"), 1.0);   // (8/4)/2, not 8/(4/2) = 4
  EXPECT_EQ(value_of("2-3-4"), -5.0);  // (2-3)-4, not 2-(3-4) = 3
  EXPECT_EQ(value_of("2*3/4"), 1.5);
  EXPECT_EQ(value_of("1 - 2*3 + 4/2"), -3.0);
  EXPECT_EQ(value_of("((2))"), 2.0);
}

TEST(AxisExpression, UnaryMinus) {
  EXPECT_EQ(value_of("-2"), -2.0);
  EXPECT_EQ(value_of("--2"), 2.0);
  EXPECT_EQ(value_of("-2*-3"), 6.0);
  EXPECT_EQ(value_of("-(1 - 4)"), 3.0);
  EXPECT_EQ(value_of("3 - -1"), 4.0);
  EXPECT_EQ(value_of("-a*b", {{"a", 2.0}, {"b", 5.0}}), -10.0);
}

TEST(AxisExpression, NumberForms) {
  EXPECT_EQ(value_of("1e-3"), 1e-3);
  EXPECT_EQ(value_of("2.5E+2"), 250.0);
  EXPECT_EQ(value_of("0.25"), 0.25);
  EXPECT_EQ(value_of(".5"), 0.5);
  EXPECT_EQ(value_of("3."), 3.0);
  EXPECT_EQ(value_of("1e3*x", {{"x", 2.0}}), 2000.0);
}

TEST(AxisExpression, NamesAreListedOnceInOrderOfAppearance) {
  std::string error;
  const auto e = AxisExpression::parse("b*a + b - rho_inf2 / a", error);
  ASSERT_TRUE(e.has_value()) << error;
  EXPECT_EQ(e->variables(), (std::vector<std::string>{"b", "a", "rho_inf2"}));
  EXPECT_EQ(e->text(), "b*a + b - rho_inf2 / a");
  EXPECT_EQ(value_of("b*a + b - rho_inf2 / a", {{"a", 2.0}, {"b", 3.0}, {"rho_inf2", 4.0}}),
            6.0 + 3.0 - 2.0);
  EXPECT_EQ(value_of("_x1", {{"_x1", 7.0}}), 7.0);
}

TEST(AxisExpression, CopiesEvaluateAlike) {
  std::string error;
  auto e = AxisExpression::parse("0.5*(1 - alpha)", error);
  ASSERT_TRUE(e.has_value());
  const AxisExpression copy = *e;
  e.reset();  // the copy shares the tree, which must outlive the original
  EXPECT_EQ(copy.evaluate([](const std::string&) { return -0.5; }), 0.75);
}

TEST(AxisExpression, DivisionByZeroIsIeeeNotAnError) {
  EXPECT_EQ(value_of("1/x", {{"x", 0.0}}), INFINITY);
  EXPECT_TRUE(std::isnan(value_of("x/x", {{"x", 0.0}})));
}

TEST(AxisExpression, ErrorsNameTheColumn) {
  EXPECT_EQ(error_of(""), "column 1: the expression is empty");
  EXPECT_EQ(error_of("   "), "column 4: the expression is empty");
  EXPECT_EQ(error_of("-1.5*"), "column 6: expected a number, a name or '(' but found the end");
  EXPECT_EQ(error_of("1 + * 2"), "column 5: expected a number, a name or '(' but found '*'");
  EXPECT_EQ(error_of("2^3"),
            "column 2: expected an operator (+ - * /) or the end but found '^' (powers are not "
            "supported)");
  EXPECT_EQ(error_of("(1 + 2"), "column 1: '(' is never closed");
  EXPECT_EQ(error_of("2*(1 + (3)"), "column 3: '(' is never closed");
  EXPECT_EQ(error_of("1 + 2)"), "column 6: unmatched ')'");
  EXPECT_EQ(error_of("(1 2)"), "column 4: expected ')' or an operator but found '2'");
  EXPECT_EQ(error_of("Alpha"),
            "column 1: expected a number, a name or '(' but found 'A' (names are lower case)");
  EXPECT_EQ(error_of("alphA"), "column 5: unexpected 'A' (names are lower case)");
  EXPECT_EQ(error_of("1e"), "column 3: the exponent of a number needs a digit");
  EXPECT_EQ(error_of("1e+"), "column 4: the exponent of a number needs a digit");
  EXPECT_EQ(error_of("3alpha"), "column 2: unexpected 'a' after a number");
  EXPECT_EQ(error_of("1.2.3"), "column 4: unexpected '.' after a number");
  EXPECT_EQ(error_of("."), "column 1: a number needs a digit");
  EXPECT_EQ(error_of("1 2"), "column 3: expected an operator (+ - * /) or the end but found '2'");
  EXPECT_EQ(error_of("a $ b"), "column 3: expected an operator (+ - * /) or the end but found '$'");
  EXPECT_EQ(error_of("+1"), "column 1: expected a number, a name or '(' but found '+'");
  EXPECT_EQ(error_of("1e999"), "column 1: the number 1e999 is out of range");
  EXPECT_EQ(error_of(std::string(300, '-') + "1"), "column 201: the expression nests too deeply");
}

TEST(AxisExpression, ParseClearsAnEarlierError) {
  std::string error = "stale";
  EXPECT_TRUE(AxisExpression::parse("1", error).has_value());
  EXPECT_EQ(error, "");
}

}  // namespace
}  // namespace impactid
