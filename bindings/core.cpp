// What only the core module (stltopo-wasm) compiles: its array table, without the full
// module's rows (STLTOPO_JS_GEOMETRY_ARRAYS) and the doc lines (a smaller download), and
// the plain Session, which adds nothing to _Session.
#include "session.h"

namespace stltopo::js {

const JsArray kJsArrays[] = {STLTOPO_JS_ARRAYS(STLTOPO_JS_ROW_NO_DOC, STLTOPO_JS_SKIP)};
const size_t kJsArrayCount = sizeof(kJsArrays) / sizeof(kJsArrays[0]);

Session* newSession(double maxTriangles, double maxBytes, double sizeHint, bool keepNormals) {
  return new Session(maxTriangles, maxBytes, sizeHint, keepNormals);
}

void registerModuleSession(const emscripten::class_<Session>&) {}

}  // namespace stltopo::js
