#pragma once
// The library's exceptions. Everything MotionMap throws derives from motionmap::Error, so an
// application boundary (the CLI's main, the GUI's worker) needs one catch clause.
//
//   try { auto clip = motionmap::io::load_clip("take.bvh"); }
//   catch (const motionmap::ParseError& e) { std::cerr << e.what(); }  // path:line:col: error: ...
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

namespace motionmap {

/// Base of every error the library reports.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Malformed input file. what() reads like a compiler diagnostic:
/// `path:line:col: error: expected <what>, found '<token>'`.
class ParseError : public Error {
 public:
  ParseError(std::string path, std::size_t line, std::size_t column, const std::string& message);

  const std::string& path() const { return m_path; }
  std::size_t line() const { return m_line; }               ///< 1-based
  std::size_t column() const { return m_column; }           ///< 1-based
  const std::string& message() const { return m_message; }  ///< the text after "error: "

 private:
  std::string m_path;
  std::size_t m_line;
  std::size_t m_column;
  std::string m_message;
};

/// A caller passed a parameter outside its valid range (names the parameter, value and range).
class ParameterError : public Error {
 public:
  using Error::Error;
};

/// A numerical method failed (no convergence, singular system, non-finite data).
class NumericalError : public Error {
 public:
  using Error::Error;
};

/// The caller's cancel callback asked to stop a long computation.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

/// Quotes a token for an error message: printable ASCII as is, other bytes as \xNN, long tokens
/// cut with "...", so garbage input never produces an unreadable or huge message.
std::string quote_token(std::string_view token);

}  // namespace motionmap
