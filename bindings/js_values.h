// What the binding files (session.cpp, full.cpp, edit.cpp) hand to JS the same way: a status as
// null or { code, message, offset?, line?, triangle?, element? } (the fields a status
// does not carry are left out), an Array as a typed-array view or copy of it and the JS
// type name of an Array; and what they take from JS the same way: a colour convention's
// name and the write options (web/src/options.js normalizeWriteOptions checked them).
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

// The JS typed array an Array<T> crosses as (the `type` of the array tables).
template <class A>
struct JsType;
template <>
struct JsType<Array<float>> {
  static constexpr const char* js = "Float32Array";
};
template <>
struct JsType<Array<double>> {
  static constexpr const char* js = "Float64Array";
};
template <>
struct JsType<Array<uint32_t>> {
  static constexpr const char* js = "Uint32Array";
};
template <>
struct JsType<Array<uint16_t>> {
  static constexpr const char* js = "Uint16Array";
};
template <>
struct JsType<Array<uint8_t>> {
  static constexpr const char* js = "Uint8Array";
};

// One row of an array table as a JS object: the fields STLTOPO_JS_ARRAYS and
// STLTOPO_JS_EDIT_ARRAYS share ({ name, group, key, element, width, type, doc }).
inline emscripten::val layoutRow(const char* name, const char* group, const char* key, const char* element, int width,
                                 const char* type, const char* doc) {
  using emscripten::val;
  val d = val::object();
  d.set("name", val(name));
  d.set("group", val(group));
  d.set("key", val(key));
  d.set("element", val(element));
  d.set("width", val(width));
  d.set("type", val(type));
  d.set("doc", val(doc));
  return d;
}

// "viscam", "magics"; anything else is None.
inline ColorConvention colorConvention(const std::string& name) {
  return name == "viscam"   ? ColorConvention::VisCam
         : name == "magics" ? ColorConvention::Magics
                            : ColorConvention::None;
}

// format "binary" | "ascii"; colors "as-mesh" | "none" | "viscam" | "magics"; name a string
// or null (each solid's own); chunkBytes <= 0 keeps the default.
inline WriteOptions writeOptions(const std::string& format, const std::string& colors, const emscripten::val& name,
                                 bool storedNormals, double chunkBytes = 0) {
  WriteOptions o;
  o.format = format == "ascii" ? Format::Ascii : Format::Binary;
  o.colors = colors == "none"     ? WriteColors::None
             : colors == "viscam" ? WriteColors::VisCam
             : colors == "magics" ? WriteColors::Magics
                                  : WriteColors::AsMesh;
  if (name.isString()) o.name = name.as<std::string>();
  o.storedNormals = storedNormals;
  if (chunkBytes > 0) o.chunkBytes = size_t(chunkBytes);
  return o;
}

}  // namespace stltopo::js
