// What both binding files (bindings.cpp, edit.cpp) hand to JS the same way: a status as
// null or { code, message, offset?, line?, triangle?, element? } (the fields a status
// does not carry are left out), and an Array as a typed-array view or copy of it.
#pragma once

#include <emscripten/val.h>

#include "stltopo/stltopo.h"

namespace stltopo::js {

inline emscripten::val status(const Status& s) {
  using emscripten::val;
  if (s.ok()) return val::null();
  val o = val::object();
  o.set("code", val(codeName(s.code)));
  o.set("message", val(s.message));
  if (s.offset != kNoOffset) o.set("offset", val(double(s.offset)));
  if (s.line != 0) o.set("line", val(double(s.line)));
  if (s.triangle != kInvalid) o.set("triangle", val(s.triangle));
  if (s.element != kInvalid) o.set("element", val(s.element));
  return o;
}

// copy = true: a view slice()d in the same expression, so the JS array owns its bytes;
// copy = false: a borrowed view into wasm memory (it detaches when memory grows).
template <class T>
emscripten::val array(const Array<T>& a, bool copy) {
  emscripten::val v(emscripten::typed_memory_view(a.size(), a.data()));
  return copy ? v.call<emscripten::val>("slice") : v;
}

}  // namespace stltopo::js
