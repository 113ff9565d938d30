#pragma once
// Serves the web front-end (clients/web, copied into a `web` folder next to the server binary at
// build time) at `/`.

#include <cstddef>
#include <filesystem>

namespace httplib {
class Server;
}

namespace hexcover::server {

/// The folder `web` next to the running executable (found through /proc/self/exe).
std::filesystem::path defaultWebRoot();

/// Registers one GET route per regular file under `root` (`/a/b.js` serves root/a/b.js) and `/`
/// for root/index.html. Only the files present now are served: the URL space is this fixed list,
/// so no request path can reach outside `root`; symbolic links, hidden files and names with
/// characters outside [A-Za-z0-9._-] are skipped. Files are streamed from disk in chunks with a
/// Content-Type from their extension. Call it after the API routes. Returns the number of files
/// served; 0 (and no route) when `root` is not a folder.
std::size_t mountWebAssets(httplib::Server& server, const std::filesystem::path& root);

}  // namespace hexcover::server
