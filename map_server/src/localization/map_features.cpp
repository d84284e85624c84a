#include "map_features.hpp"

namespace socc::localization {

const IndexedFeatures& MapFeatures::get() {
  std::call_once(once_, [this] {
    built_ = std::make_unique<const IndexedFeatures>(describeOriented(keypoints_, params_));
    keypoints_.reset();
  });
  return *built_;
}

}  // namespace socc::localization
