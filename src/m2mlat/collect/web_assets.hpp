// The dashboard's web page (web/dashboard.html, .js, .css), compiled into the executable so the
// coordinator serves it without any file beside it and without the network. The definitions are
// generated at build time by cmake/embed_assets.cmake from the files in web/.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace m2mlat::collect {

struct WebAsset {
  std::string_view path;          // URL path, e.g. "/dashboard.js"
  std::string_view content_type;  // e.g. "text/javascript; charset=utf-8"
  std::string_view bytes;         // the file's contents, byte for byte
};

// Every embedded file, sorted by path.
std::span<const WebAsset> web_assets();
// The file served at `path` ("/" is "/dashboard.html"), or nullptr.
const WebAsset* find_web_asset(std::string_view path);

}  // namespace m2mlat::collect
