// RemoteBackend: the C ABI's calls forwarded to a `quarry serve` process (api/server.h) over
// ZeroMQ, bulk arrays through shared memory when both run on one host (api/wire.h).
#pragma once

#include <memory>

#include "api/backend.h"

namespace quarry::api {

// Connects to the server at info.endpoint and attaches to its simulation. Throws ApiError
// (TRANSPORT, TIMEOUT, VERSION) when it cannot.
std::unique_ptr<Backend> open_remote(const quarry_open_info& info);

}  // namespace quarry::api
