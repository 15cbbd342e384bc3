// EditableMesh attributes: the engine (slots, defaults, rules, pending writes) and the
// attribute API. See impl.h.
#include "edit/impl.h"

namespace stltopo {
using Impl = EditableMesh::Impl;

namespace {

constexpr uint32_t kMaxComponents = 64;

double readValue(ValueType t, const uint8_t* p) {
  switch (t) {
    case ValueType::U8: return *p;
    case ValueType::I8: return int8_t(*p);
    case ValueType::U16: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case ValueType::I16: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case ValueType::U32: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case ValueType::I32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case ValueType::F32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case ValueType::F64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
  return 0;
}

template <class T>
void storeInt(double x, uint8_t* p, double lo, double hi) {
  double r = std::isnan(x) ? 0 : std::min(hi, std::max(lo, std::nearbyint(x)));
  T v = T(r);
  std::memcpy(p, &v, sizeof v);
}

void writeValue(ValueType t, double x, uint8_t* p) {
  switch (t) {
    case ValueType::U8: storeInt<uint8_t>(x, p, 0, 255); break;
    case ValueType::I8: storeInt<int8_t>(x, p, -128, 127); break;
    case ValueType::U16: storeInt<uint16_t>(x, p, 0, 65535); break;
    case ValueType::I16: storeInt<int16_t>(x, p, -32768, 32767); break;
    case ValueType::U32: storeInt<uint32_t>(x, p, 0, 4294967295.0); break;
    case ValueType::I32: storeInt<int32_t>(x, p, -2147483648.0, 2147483647.0); break;
    case ValueType::F32: {
      float v = float(x);
      std::memcpy(p, &v, 4);
      break;
    }
    case ValueType::F64: std::memcpy(p, &x, 8); break;
  }
}

}  // namespace

size_t valueTypeSize(ValueType t) {
  switch (t) {
    case ValueType::U8:
    case ValueType::I8: return 1;
    case ValueType::U16:
    case ValueType::I16: return 2;
    case ValueType::U32:
    case ValueType::I32:
    case ValueType::F32: return 4;
    case ValueType::F64: return 8;
  }
  return 1;
}

bool EditableMesh::Impl::reserveAttributes(M& m, Element e, size_t n) {
  for (Attribute& a : m.attributes_)
    if (a.view.element == e && !growTo(a.bytes, n * stride(a))) return false;
  return true;
}

void EditableMesh::Impl::appendDefaults(M& m, Element e) {
  for (Attribute& a : m.attributes_) {
    if (a.view.element != e) continue;
    size_t s = stride(a), n = a.bytes.size();
    (void)a.bytes.resize(n + s);
    writeDefault(a, a.bytes.data() + n);
    a.view.data = a.bytes.data();
    a.view.count = a.bytes.size() / s;
  }
}

void EditableMesh::Impl::writeDefault(const Attribute& a, uint8_t* p) {
  size_t w = valueTypeSize(a.view.type);
  for (uint32_t k = 0; k < a.view.components; ++k) writeValue(a.view.type, a.defaultValue[k], p + k * w);
}

void EditableMesh::Impl::resetDefault(M& m, Element e, size_t i) {
  for (Attribute& a : m.attributes_)
    if (a.view.element == e) writeDefault(a, at(a, i));
}

void EditableMesh::Impl::copySlot(M& m, Element e, size_t from, size_t to) {
  for (Attribute& a : m.attributes_)
    if (a.view.element == e) std::memmove(at(a, to), at(a, from), stride(a));
}

bool EditableMesh::Impl::evalRule(const Attribute& a, bool merge, const uint8_t* x, const uint8_t* y, double t,
                                  uint8_t* out) {
  const Rule r = merge ? a.rules.merge : a.rules.split;
  const size_t w = valueTypeSize(a.view.type), s = w * a.view.components;
  switch (r) {
    case Rule::KeepFirst: std::memmove(out, x, s); return true;
    case Rule::Fail:
      if (std::memcmp(x, y, s) != 0) return false;
      std::memmove(out, x, s);
      return true;
    case Rule::Average:
    case Rule::Custom: {
      double xd[kMaxComponents], yd[kMaxComponents], od[kMaxComponents];
      for (uint32_t k = 0; k < a.view.components; ++k) {
        xd[k] = readValue(a.view.type, x + k * w);
        yd[k] = readValue(a.view.type, y + k * w);
      }
      if (r == Rule::Average) {
        for (uint32_t k = 0; k < a.view.components; ++k) od[k] = (1 - t) * xd[k] + t * yd[k];
      } else {
        const RuleCallback& fn = merge ? a.rules.mergeFn : a.rules.splitFn;
        if (!fn || !fn(xd, yd, t, od, a.view.components)) return false;
      }
      for (uint32_t k = 0; k < a.view.components; ++k) writeValue(a.view.type, od[k], out + k * w);
      return true;
    }
  }
  return false;
}

void EditableMesh::Impl::writePending(M& m, const PendingWrites& pw) {
  for (const Pending& p : pw.list) {
    Attribute& a = m.attributes_[p.attr];
    const uint8_t* src = pw.bytes.data() + p.offset;
    if (a.view.element != Element::Edge) {
      std::memcpy(at(a, p.id), src, stride(a));
      continue;
    }
    // Every pair of the edge (one, unless the edge is cut).
    forEachEdgeSide(m, p.u, p.v, [&](uint32_t s) {
      uint32_t h = m.sideHalfedge_[s];
      std::memcpy(at(a, h >> 1), src, stride(a));
    });
  }
}

// ============================================================================ attributes

Status EditableMesh::Impl::addAttribute(const std::string& name, Element element, ValueType type, uint32_t components,
                                        const void* values, const AttributeRules& rules, const double* defaultValue) {
  if (name.empty()) return badArgument("an attribute needs a name");
  if (components == 0 || components > kMaxComponents)
    return badArgument(detail::format("an attribute has 1 to %u components, not %u", kMaxComponents, components));
  if ((rules.merge == Rule::Custom && !rules.mergeFn) || (rules.split == Rule::Custom && !rules.splitFn))
    return badArgument("a custom rule needs its callback");
  STLTOPO_TRY {
    Attribute a;
    a.name = name;
    a.view.element = element;
    a.view.type = type;
    a.view.components = components;
    a.rules = rules;
    a.defaultValue.assign(components, 0.0);
    if (defaultValue)
      for (uint32_t k = 0; k < components; ++k) a.defaultValue[k] = defaultValue[k];
    const size_t n = Impl::elementCount(*this, element), s = Impl::stride(a);
    if (!a.bytes.resize(n * s)) return detail::oom(kEditArrays);
    if (values && n > 0) {
      std::memcpy(a.bytes.data(), values, n * s);
    } else {
      for (size_t i = 0; i < n; ++i) Impl::writeDefault(a, a.bytes.data() + i * s);
    }
    a.view.data = a.bytes.data();
    a.view.count = n;
    for (Attribute& x : attributes_)
      if (x.name == name) {
        x = std::move(a);
        x.view.data = x.bytes.data();
        return Status{};
      }
    attributes_.push_back(std::move(a));
    attributes_.back().view.data = attributes_.back().bytes.data();
  }
  STLTOPO_CATCH { return detail::oom(kEditArrays); }
  return Status{};
}

const AttributeView* EditableMesh::Impl::attribute(const std::string& name) const {
  for (const Attribute& a : attributes_)
    if (a.name == name) {
      // data and count follow the slot arrays (the bytes may have moved since).
      AttributeView& v = const_cast<AttributeView&>(a.view);
      v.data = const_cast<uint8_t*>(a.bytes.data());
      v.count = a.bytes.size() / Impl::stride(a);
      return &a.view;
    }
  return nullptr;
}

bool EditableMesh::Impl::removeAttribute(const std::string& name) {
  for (size_t i = 0; i < attributes_.size(); ++i)
    if (attributes_[i].name == name) {
      attributes_.erase(attributes_.begin() + long(i));
      return true;
    }
  return false;
}

std::vector<std::string> EditableMesh::Impl::attributeNames() const {
  std::vector<std::string> out;
  for (const Attribute& a : attributes_) out.push_back(a.name);
  return out;
}

}  // namespace stltopo
