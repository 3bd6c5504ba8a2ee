#include "odometry/estimator/gnss/gnss_enu_origin.h"

namespace uf::estimator {

Expected<Eigen::Vector3d> GnssEnuOrigin::ToEnu(const GnssFix& fix) {
  if (!frame_) {
    Expected<EnuFrame> frame = EnuFrame::Create({fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
    if (!frame) return Status::Error("GNSS ENU origin: " + frame.error());
    frame_ = std::move(frame).value();
  }
  return frame_->EnuFromGeodetic(FixGeodetic(fix));
}

}  // namespace uf::estimator
