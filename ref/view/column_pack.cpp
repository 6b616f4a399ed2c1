// PackColumns / UnpackColumns (packed.h): repeated columns as references, id-like text columns as
// one template and delta-coded integers. The page's twin is site/view.js expandColumns.
#include <cctype>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "view/packed.h"

namespace dynref::view {
namespace {

using nlohmann::json;

// `s` split into texts and integers (an optional '-' then digits): t0 n0 t1 n1 ... tk. False when
// an integer would not print back as itself (leading zero, "-0") or has more than 15 digits (the
// page's doubles hold it exactly, and so do the deltas).
bool SplitIntegers(const std::string& s, std::vector<std::string>* texts, std::vector<int64_t>* ints) {
  texts->assign(1, "");
  ints->clear();
  for (size_t i = 0; i < s.size();) {
    const bool minus = s[i] == '-' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1]));
    if (!minus && !std::isdigit(static_cast<unsigned char>(s[i]))) {
      texts->back() += s[i++];
      continue;
    }
    size_t j = i + (minus ? 1 : 0);
    const size_t digits = j;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
    const std::string token = s.substr(i, j - i);
    if (j - digits > 15 || (s[digits] == '0' && j - digits > 1) || token == "-0") return false;
    ints->push_back(std::stoll(token));
    texts->push_back("");
    i = j;
  }
  return true;
}

// {"c", "t", "n"} for a column of texts sharing one template, else null.
json TemplateColumn(const json& col) {
  if (col.empty()) return nullptr;
  std::vector<std::string> texts, first_texts;
  std::vector<int64_t> ints;
  std::vector<std::vector<int64_t>> slots;
  for (const json& v : col) {
    if (!v.is_string() || !SplitIntegers(v.get_ref<const std::string&>(), &texts, &ints)) return nullptr;
    if (slots.empty() && first_texts.empty()) first_texts = texts, slots.resize(ints.size());
    if (texts != first_texts) return nullptr;
    for (size_t k = 0; k < ints.size(); ++k) slots[k].push_back(ints[k]);
  }
  json n = json::array();
  for (const std::vector<int64_t>& s : slots) {
    json d = json::array();
    for (size_t i = 0; i < s.size(); ++i) d.push_back(i == 0 ? s[0] : s[i] - s[i - 1]);
    n.push_back(std::move(d));
  }
  return {{"c", col.size()}, {"t", first_texts}, {"n", std::move(n)}};
}

json ExpandTemplate(const json& t) {
  const json& texts = t.at("t");
  const json& n = t.at("n");
  std::vector<int64_t> cur(n.size(), 0);
  json col = json::array();
  for (size_t i = 0; i < t.at("c").get<size_t>(); ++i) {
    std::string s = texts.at(0).get<std::string>();
    for (size_t k = 0; k < n.size(); ++k) {
      cur[k] = i == 0 ? n[k].at(0).get<int64_t>() : cur[k] + n[k].at(i).get<int64_t>();
      s += std::to_string(cur[k]) + texts.at(k + 1).get<std::string>();
    }
    col.push_back(std::move(s));
  }
  return col;
}

}  // namespace

json PackColumns(const json& cols) {
  std::map<std::string, json> first;  // column text -> [schema id, index] of its first occurrence
  json out = json::object();
  for (const auto& [sid, columns] : cols.items()) {
    json packed = json::array();
    for (size_t i = 0; i < columns.size(); ++i) {
      auto [it, fresh] = first.emplace(columns[i].dump(), json::array({std::stoi(sid), i}));
      if (!fresh) {
        packed.push_back({{"=", it->second}});
        continue;
      }
      json t = TemplateColumn(columns[i]);
      packed.push_back(t.is_null() ? columns[i] : std::move(t));
    }
    out[sid] = std::move(packed);
  }
  return out;
}

json UnpackColumns(const json& packed) {
  json out = json::object();
  for (const auto& [sid, columns] : packed.items())
    for (const json& c : columns) out[sid].push_back(c.is_object() && c.contains("t") ? ExpandTemplate(c) : c);
  for (auto& [sid, columns] : out.items())
    for (json& c : columns)
      if (c.is_object()) {
        const json& ref = c.at("=");
        const json& target = out.at(std::to_string(ref.at(0).get<int>())).at(ref.at(1).get<size_t>());
        if (!target.is_array()) throw InputError("view data", "a column refers to a column that is not plain");
        c = target;
      }
  return out;
}

}  // namespace dynref::view
