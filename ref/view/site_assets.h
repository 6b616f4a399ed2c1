// The page of `dynref view`: ref/view/site/{index.html,view.js,view.css}, embedded at build time
// (embed_assets.cmake) so the executable needs no resource folder.
#pragma once
#include <string>
#include <vector>

namespace dynref::view {

struct SiteAsset {
  std::string name;     // path in the site, e.g. "index.html"
  std::string content;
};
const std::vector<SiteAsset>& SiteAssets();

}  // namespace dynref::view
