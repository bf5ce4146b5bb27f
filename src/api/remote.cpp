// RemoteBackend (remote.h): not built yet in this commit; opening an endpoint is refused.
#include "api/remote.h"

namespace quarry::api {

std::unique_ptr<Backend> open_remote(const quarry_open_info& info) {
  throw ApiError(QUARRY_ERROR_UNSUPPORTED,
                 std::string("quarry_open: endpoint '") + info.endpoint + "': remote simulations are not available in this build");
}

}  // namespace quarry::api
