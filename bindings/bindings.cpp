// Embind registration of what both wasm modules have: the load's session (`_Session`, its
// adapters in session.cpp) and the free functions. Raw, underscore-prefixed API only: the
// friendly JavaScript API lives in web/src. Each module adds its own part of `_Session`
// (registerModuleSession) and its own classes from the file only it compiles: core.cpp or
// full.cpp (bindings/CMakeLists.txt lists each module's files).
#include <emscripten/bind.h>

#include "session.h"

EMSCRIPTEN_BINDINGS(stltopo) {
  using namespace emscripten;
  using stltopo::js::Session;
  class_<Session> session("_Session");
  session.constructor(&stltopo::js::newSession)
      .function("buffer", &Session::buffer)
      .function("feed", &Session::feed)
      .function("finish", &Session::finish)
      .function("bytesRead", &Session::bytesRead)
      .function("meta", &Session::meta)
      .function("infoJson", &Session::infoJson)
      .function("infoText", &Session::infoText)
      .function("messageBytes", &Session::messageBytes)
      .function("array", &Session::array)
      .function("upload", &Session::upload)
      .function("setCounts", &Session::setCounts)
      .function("setMeta", &Session::setMeta)
      .function("validate", &Session::validate);
  stltopo::js::registerModuleSession(session);
  function("_setThreads", &stltopo::js::setThreads);
  function("_threads", &stltopo::js::threads);
#if defined(__EMSCRIPTEN_PTHREADS__)
  // Test-only (tests/js/threads.test.mjs): the stages' split grain and the split count
  // (stltopo::setParallelGrainForTesting), so that the small fixtures take the threaded paths.
  function("_setParallelGrainForTesting", +[](double g) { stltopo::setParallelGrainForTesting(g > 0 ? size_t(g) : 0); });
  function("_parallelSplitsForTesting", +[]() { return double(stltopo::parallelSplitsForTesting()); });
#endif
  function("_arrayLayout", &stltopo::js::arrayLayout);
  function("_errorJson", &stltopo::js::errorJson);
  function("_codeName", &stltopo::js::codeNameAt);
  function("_codeCount", &stltopo::js::codeCount);
}
