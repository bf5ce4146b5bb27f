// The one mapping from the exceptions the backends and the engine throw to the C ABI's status
// codes and texts (api/backend.h), shared by the C functions and by `quarry serve`.
#include "api/backend.h"

#include <fmt/format.h>

#include <exception>
#include <filesystem>
#include <new>

#include "api/wire.h"
#include "core/diagnostics.h"

namespace quarry::api {

Failure current_failure(const char* call) {
  const auto named = [call](const std::string& text) { return fmt::format("{}: {}", call, text); };
  try {
    throw;
  } catch (const ApiError& e) {
    const std::string text = e.what();
    return {e.status(), text.rfind("quarry_", 0) == 0 ? text : named(text)};
  } catch (const UserError& e) {
    return {QUARRY_ERROR_INPUT, named(e.diagnostics().format())};
  } catch (const PhysicsError& e) {
    return {QUARRY_ERROR_PHYSICS, named(e.what())};
  } catch (const wire::WireError& e) {  // a reply that does not follow the framing (remote handles)
    return {QUARRY_ERROR_TRANSPORT,
            named(fmt::format("the server's reply is malformed: {}", e.what()))};
  } catch (const std::filesystem::filesystem_error& e) {
    return {QUARRY_ERROR_IO, named(e.what())};
  } catch (const std::bad_alloc&) {
    return {QUARRY_ERROR_INTERNAL, named("out of memory")};
  } catch (const std::exception& e) {
    return {QUARRY_ERROR_INTERNAL, named(fmt::format("internal error: {}", e.what()))};
  } catch (...) {
    return {QUARRY_ERROR_INTERNAL, named("internal error: an exception of unknown type")};
  }
}

}  // namespace quarry::api
