// Per-run state shared by the stages of one method (e.g. SGDO's dynamic mask of the current
// frame, written by sgdo.mask and read by sgdo.coarse and the dense map). One SharedState per
// Session, so two runs in one process never see each other's state (issue 12).
#pragma once
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>

namespace dynref {

class SharedState {
 public:
  // The object stored under `key`, default-constructed on first use. std::logic_error when the
  // key already holds another type.
  template <typename T>
  std::shared_ptr<T> Get(const std::string& key) {
    auto it = entries_.find(key);
    if (it == entries_.end()) {
      auto value = std::make_shared<T>();
      entries_.emplace(key, Entry{value, &typeid(T)});
      return value;
    }
    if (*it->second.type != typeid(T)) throw std::logic_error("shared state '" + key + "' holds another type");
    return std::static_pointer_cast<T>(it->second.value);
  }
  bool Has(const std::string& key) const { return entries_.count(key) > 0; }

 private:
  struct Entry {
    std::shared_ptr<void> value;
    const std::type_info* type;
  };
  std::map<std::string, Entry> entries_;
};

}  // namespace dynref
