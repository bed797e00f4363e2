#include "harness/subprocess.h"

#include <new>
#include <sstream>

#include <fmt/format.h>

#include "solvers/base/error.h"

namespace db::harness {

std::string pct_encode(const std::string& s) {
  std::string o;
  for (unsigned char c : s) {
    if (c <= ' ' || c == '%' || c == '=' || c >= 0x7f) o += fmt::format("%{:02X}", c);
    else o += static_cast<char>(c);
  }
  return o;
}

std::string pct_decode(const std::string& s) {
  std::string o;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      o += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      o += s[i];
    }
  }
  return o;
}

std::vector<std::pair<std::string, std::string>> parse_result_line(const std::string& out, const std::string& tag) {
  const std::string head = tag + " ";
  const std::size_t at = out.rfind(head);
  if (at == std::string::npos || (at > 0 && out[at - 1] != '\n'))
    throw Error(fmt::format("no {} line in the child's output", tag));
  std::string line = out.substr(at + head.size());
  line = line.substr(0, line.find('\n'));
  std::vector<std::pair<std::string, std::string>> fields;
  std::istringstream in(line);
  std::string tok;
  while (in >> tok) {
    const std::size_t eq = tok.find('=');
    if (eq == std::string::npos) throw Error(fmt::format("malformed {} field: {}", tag, tok));
    fields.emplace_back(tok.substr(0, eq), pct_decode(tok.substr(eq + 1)));
  }
  return fields;
}

CellOutcome run_guarded_cell(const std::function<void()>& measure) {
  CellOutcome o;
  try {
    measure();
  } catch (const BudgetError& e) {
    o.status = "#over";
    o.message = e.what();
    o.exit_code = exit_code(e);
  } catch (const std::bad_alloc&) {
    o.status = "error";
    o.message = "out of memory (std::bad_alloc; the cell's address-space limit may have been reached)";
    o.exit_code = 1;
  } catch (const std::exception& e) {
    o.status = "error";
    o.message = e.what();
    o.exit_code = exit_code(e);
  }
  return o;
}

}  // namespace db::harness
