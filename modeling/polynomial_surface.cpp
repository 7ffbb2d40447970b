#include "modeling/polynomial_surface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <system_error>
#include <utility>

#include "modeling/errors.h"

namespace flexure::modeling {

namespace {

// Powers above this are taken for typos (x^1000 instead of x^10).
constexpr int kMaxPower = 64;

// x^k by repeated squaring; x^0 = 1 (also for x = 0), the convention the derivatives rely on.
double power(double x, int k) {
  double result = 1.0;
  while (k > 0) {
    if (k & 1) result *= x;
    x *= x;
    k >>= 1;
  }
  return result;
}

// Shortest decimal that reads back to the same double.
std::string formatNumber(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

[[noreturn]] void fail(std::string_view spec, const std::string& what) {
  throw InputError("bad surface '" + std::string(spec) + "': " + what +
                   "; expected quadratic:a,b,c or polynomial:x^3-3*x*y^2");
}

// Recursive-descent reader of  expr := [sign] term (sign term)*,  term := factor ('*' factor)*,
// factor := number | x ['^' power] | y ['^' power], with blanks allowed between tokens.
class ExpressionParser {
 public:
  ExpressionParser(std::string_view spec, std::string_view text) : spec_(spec), text_(text) {}

  std::vector<Monomial> parse() {
    std::vector<Monomial> terms;
    skipBlanks();
    if (atEnd()) fail(spec_, "the polynomial is empty");
    bool negative = false;
    if (peek() == '+' || peek() == '-') negative = get() == '-';
    while (true) {
      Monomial term = parseTerm();
      if (negative) term.coefficient = -term.coefficient;
      terms.push_back(term);
      skipBlanks();
      if (atEnd()) break;
      const char sign = get();
      if (sign != '+' && sign != '-') unexpected(position_ - 1, "'+', '-' or '*'");
      negative = sign == '-';
    }
    return terms;
  }

  // The coefficient `name`: one number filling all of `text` (blanks around it allowed), with an
  // optional sign.
  static double parseNumber(std::string_view spec, char name, std::string_view text) {
    ExpressionParser parser(spec, text);
    parser.skipBlanks();
    bool negative = false;
    if (!parser.atEnd() && (parser.peek() == '+' || parser.peek() == '-')) {
      negative = parser.get() == '-';
    }
    const std::string notNumber =
        std::string(1, name) + " = '" + std::string(text) + "' is not a number";
    if (parser.atEnd() || !startsNumber(parser.peek())) fail(spec, notNumber);
    const double value = parser.number();
    parser.skipBlanks();
    if (!parser.atEnd()) fail(spec, notNumber);
    return negative ? -value : value;
  }

 private:
  static bool startsNumber(char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || c == '.';
  }

  Monomial parseTerm() {
    Monomial term{1.0, 0, 0};
    while (true) {
      skipBlanks();
      if (atEnd()) unexpected(position_, "a number, x or y");
      const char c = peek();
      if (startsNumber(c)) {
        term.coefficient *= number();
      } else if (c == 'x' || c == 'y') {
        ++position_;
        int exponent = 1;
        skipBlanks();
        if (!atEnd() && peek() == '^') {
          ++position_;
          exponent = powerValue();
        }
        int& total = c == 'x' ? term.xPower : term.yPower;
        total += exponent;
        if (total > kMaxPower) {
          fail(spec_, std::string("the power of ") + c + " exceeds " + std::to_string(kMaxPower));
        }
      } else {
        unexpected(position_, "a number, x or y");
      }
      skipBlanks();
      if (atEnd() || peek() != '*') return term;
      ++position_;
    }
  }

  // A finite decimal number without sign (std::from_chars: digits, point, exponent).
  double number() {
    const char* begin = text_.data() + position_;
    const char* end = text_.data() + text_.size();
    double value = 0.0;
    const auto result = std::from_chars(begin, end, value);
    if (result.ec == std::errc::result_out_of_range || !std::isfinite(value)) {
      fail(spec_, "the number '" + std::string(begin, result.ptr) + "' is out of range");
    }
    if (result.ec != std::errc() || result.ptr == begin) {
      unexpected(position_, "a number");
    }
    position_ += static_cast<std::size_t>(result.ptr - begin);
    return value;
  }

  // A whole number 0 … kMaxPower after '^'.
  int powerValue() {
    skipBlanks();
    const std::size_t start = position_;
    int value = 0;
    while (!atEnd() && std::isdigit(static_cast<unsigned char>(peek()))) {
      value = std::min(value * 10 + (get() - '0'), kMaxPower + 1);
    }
    if (position_ == start) unexpected(start, "a whole number ≥ 0 after '^'");
    if (value > kMaxPower)
      fail(spec_, "powers above " + std::to_string(kMaxPower) + " are not supported");
    return value;
  }

  [[noreturn]] void unexpected(std::size_t at, const std::string& wanted) const {
    const std::string found =
        at >= text_.size() ? "the end" : "'" + std::string(1, text_[at]) + "'";
    fail(spec_, "expected " + wanted + " at " + found + " (character " + std::to_string(at + 1) +
                    " of '" + std::string(text_) + "')");
  }

  bool atEnd() const { return position_ >= text_.size(); }
  char peek() const { return text_[position_]; }
  char get() { return text_[position_++]; }
  void skipBlanks() {
    while (!atEnd() && std::isspace(static_cast<unsigned char>(peek()))) ++position_;
  }

  std::string_view spec_;
  std::string_view text_;
  std::size_t position_ = 0;
};

// True when the terms are a x² + b xy + c y² in the order quadratic() makes them.
bool isQuadraticForm(const std::vector<Monomial>& terms) {
  return terms.size() == 3 && terms[0].xPower == 2 && terms[0].yPower == 0 &&
         terms[1].xPower == 1 && terms[1].yPower == 1 && terms[2].xPower == 0 &&
         terms[2].yPower == 2;
}

// "c*x^i*y^j" with unit factors left out ("x", "-y^2", "3", "-1").
std::string formatTerm(const Monomial& term) {
  std::string factors;
  const auto appendFactor = [&factors](char variable, int power) {
    if (power == 0) return;
    if (!factors.empty()) factors += '*';
    factors += variable;
    if (power != 1) factors += '^' + std::to_string(power);
  };
  appendFactor('x', term.xPower);
  appendFactor('y', term.yPower);
  if (factors.empty()) return formatNumber(term.coefficient);
  if (term.coefficient == 1.0) return factors;
  if (term.coefficient == -1.0) return "-" + factors;
  return formatNumber(term.coefficient) + "*" + factors;
}

}  // namespace

PolynomialSurface::PolynomialSurface(std::vector<Monomial> terms) : terms_(std::move(terms)) {
  for (const Monomial& t : terms_) {
    if (!std::isfinite(t.coefficient) || t.xPower < 0 || t.yPower < 0) {
      throw InputError("bad surface term " + formatNumber(t.coefficient) + "*x^" +
                       std::to_string(t.xPower) + "*y^" + std::to_string(t.yPower) +
                       ": coefficients must be finite and powers whole numbers ≥ 0");
    }
  }
}

PolynomialSurface PolynomialSurface::quadratic(double a, double b, double c) {
  return PolynomialSurface({{a, 2, 0}, {b, 1, 1}, {c, 0, 2}});
}

PolynomialSurface PolynomialSurface::parse(std::string_view spec) {
  const std::size_t colon = spec.find(':');
  if (colon == std::string_view::npos)
    fail(spec, "no 'quadratic:' or 'polynomial:' before the terms");
  const std::string_view kind = spec.substr(0, colon);
  const std::string_view body = spec.substr(colon + 1);
  if (kind == "quadratic") {
    double coefficients[3];
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
      const std::size_t comma = body.find(',', start);
      if ((k < 2) == (comma == std::string_view::npos)) {
        const std::size_t count =
            1 + static_cast<std::size_t>(std::count(body.begin(), body.end(), ','));
        fail(spec, "quadratic takes exactly 3 numbers a,b,c, got " + std::to_string(count));
      }
      const std::size_t end = k < 2 ? comma : body.size();
      coefficients[k] =
          ExpressionParser::parseNumber(spec, "abc"[k], body.substr(start, end - start));
      start = end + 1;
    }
    return quadratic(coefficients[0], coefficients[1], coefficients[2]);
  }
  if (kind == "polynomial") {
    return PolynomialSurface(ExpressionParser(spec, body).parse());
  }
  fail(spec, "unknown kind '" + std::string(kind) + "'");
}

double PolynomialSurface::height(double x, double y) const {
  double z = 0.0;
  for (const Monomial& t : terms_) z += t.coefficient * power(x, t.xPower) * power(y, t.yPower);
  return z;
}

Eigen::Vector2d PolynomialSurface::gradient(double x, double y) const {
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  for (const Monomial& t : terms_) {
    if (t.xPower > 0)
      g.x() += t.coefficient * t.xPower * power(x, t.xPower - 1) * power(y, t.yPower);
    if (t.yPower > 0)
      g.y() += t.coefficient * t.yPower * power(x, t.xPower) * power(y, t.yPower - 1);
  }
  return g;
}

Eigen::Matrix2d PolynomialSurface::hessian(double x, double y) const {
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  for (const Monomial& t : terms_) {
    const int i = t.xPower;
    const int j = t.yPower;
    if (i > 1) h(0, 0) += t.coefficient * i * (i - 1) * power(x, i - 2) * power(y, j);
    if (i > 0 && j > 0) h(0, 1) += t.coefficient * i * j * power(x, i - 1) * power(y, j - 1);
    if (j > 1) h(1, 1) += t.coefficient * j * (j - 1) * power(x, i) * power(y, j - 2);
  }
  h(1, 0) = h(0, 1);
  return h;
}

Eigen::Vector3d PolynomialSurface::unitNormal(double x, double y) const {
  const Eigen::Vector2d g = gradient(x, y);
  return Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
}

std::string PolynomialSurface::spec() const {
  if (isQuadraticForm(terms_)) {
    return "quadratic:" + formatNumber(terms_[0].coefficient) + "," +
           formatNumber(terms_[1].coefficient) + "," + formatNumber(terms_[2].coefficient);
  }
  // No terms is the zero function; "0" reads back as one zero constant term.
  if (terms_.empty()) return "polynomial:0";
  std::string expression;
  for (const Monomial& term : terms_) {
    const std::string text = formatTerm(term);
    if (!expression.empty() && text.front() != '-') expression += '+';
    expression += text;
  }
  return "polynomial:" + expression;
}

void applyHeightField(const PolynomialSurface& surface, Positions& positions) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    positions(v, 2) = surface.height(positions(v, 0), positions(v, 1));
  }
}

}  // namespace flexure::modeling
