#include "stltopo.h"

namespace stltopo {

const char* codeName(Code c) {
  switch (c) {
    case Code::Ok: return "ok";
    case Code::Empty: return "empty";
    case Code::NotStl: return "not-stl";
    case Code::Truncated: return "truncated";
    case Code::UnexpectedEnd: return "unexpected-end";
    case Code::AsciiSyntax: return "ascii-syntax";
    case Code::NonFinite: return "non-finite";
    case Code::TooLarge: return "too-large";
    case Code::OutOfMemory: return "out-of-memory";
    case Code::InvalidArgument: return "invalid-argument";
    case Code::Aborted: return "aborted";
    case Code::Invalid: return "invalid";
    case Code::TrailingBytes: return "trailing-bytes";
    case Code::MissingEndsolid: return "missing-endsolid";
    case Code::NameTruncated: return "name-truncated";
  }
  return "unknown";
}

const char* formatName(Format f) {
  switch (f) {
    case Format::Binary: return "binary";
    case Format::Ascii: return "ascii";
    default: return "unknown";
  }
}

const char* colorConventionName(ColorConvention c) {
  switch (c) {
    case ColorConvention::VisCam: return "viscam";
    case ColorConvention::Magics: return "magics";
    default: return "none";
  }
}

}  // namespace stltopo
