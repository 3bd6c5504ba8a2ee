#include "odometry/io/folders/kitti_raw_calibration.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <sstream>

#include "odometry/io/folders/kitti_raw_files.h"

namespace uf {
namespace {

namespace fs = std::filesystem;

Expected<KittiCalibValues> ReadCalib(const fs::path& date_folder, const char* name) {
  const fs::path file = date_folder / name;
  std::error_code error;
  if (!fs::is_regular_file(file, error))
    return Status::Error(file.string() + ": missing; a KITTI raw drive needs " + name +
                         " in its date folder (looked in " + date_folder.string() + ")");
  return ReadKittiCalibFile(file);
}

// The rotation nearest to `R` (KITTI prints 7 digits, so R^T R = I holds to ~1e-6 only): its polar factor.
Expected<Eigen::Matrix3d> Rotation(const std::vector<double>& row_major, const std::string& where) {
  const Eigen::Matrix3d R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(row_major.data());
  const double error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(error < 1e-4) || R.determinant() < 0) {
    std::ostringstream text;
    text << where << " is not a rotation (max |R^T R - I| = " << error << ", det = " << R.determinant()
         << ")";
    return Status::Error(text.str());
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return Eigen::Matrix3d(svd.matrixU() * svd.matrixV().transpose());
}

// `R: 9 numbers`, `T: 3 numbers` of `file` as the transform x_to = R x_from + T.
Expected<SE3> RigidTransform(const KittiCalibValues& values, const std::string& r_key,
                             const std::string& t_key, const fs::path& file) {
  auto r = CalibNumbers(values, r_key, 9, file);
  if (!r) return r.status();
  auto t = CalibNumbers(values, t_key, 3, file);
  if (!t) return t.status();
  auto R = Rotation(*r, file.string() + ": " + r_key);
  if (!R) return R.status();
  return SE3(SO3(*R), Eigen::Vector3d((*t)[0], (*t)[1], (*t)[2]));
}

Expected<std::array<int, 2>> ImageSize(const KittiCalibValues& values, const std::string& key,
                                       const fs::path& file) {
  auto size = CalibNumbers(values, key, 2, file);
  if (!size) return size.status();
  const double w = (*size)[0], h = (*size)[1];
  if (!(w >= 1 && h >= 1 && w <= 65536 && h <= 65536 && w == std::floor(w) && h == std::floor(h)))
    return Status::Error(file.string() + ": " + key + " must be a width and height in pixels");
  return std::array<int, 2>{static_cast<int>(w), static_cast<int>(h)};
}

Expected<std::shared_ptr<const CameraModel>> Validated(const PinholeRadtanIntrinsics& intrinsics,
                                                       const std::string& where) {
  auto model = std::make_shared<PinholeRadtan>(intrinsics);
  if (Status s = model->Validate(); !s.ok()) return Status::Error(where + ": " + s.message());
  return std::shared_ptr<const CameraModel>(std::move(model));
}

// The rectified camera: pinhole from P_rect_0i, and the pose of its frame in cam0's, T_cam0_recti.
Expected<KittiRawCamera> RectifiedCamera(const KittiCalibValues& values, const std::string& i,
                                         const fs::path& file, SE3& T_cam0_camera) {
  auto size = ImageSize(values, "S_rect_" + i, file);
  if (!size) return size.status();
  auto p = CalibNumbers(values, "P_rect_" + i, 12, file);
  if (!p) return p.status();
  auto r_rect = CalibNumbers(values, "R_rect_00", 9, file);
  if (!r_rect) return r_rect.status();
  auto R_rect = Rotation(*r_rect, file.string() + ": R_rect_00");
  if (!R_rect) return R_rect.status();
  const Eigen::Matrix<double, 3, 4, Eigen::RowMajor> P(p->data());
  const Eigen::Matrix3d K = P.leftCols<3>();
  const Eigen::Vector3d t_i = K.fullPivLu().solve(P.col(3));  // X_recti = X_rect0 + t_i
  if (!t_i.allFinite()) return Status::Error(file.string() + ": P_rect_" + i + " has a singular K");
  T_cam0_camera = SE3(SO3(*R_rect), t_i).inverse();  // X_recti = R_rect_00 X_cam0 + t_i
  PinholeRadtanIntrinsics intrinsics;
  intrinsics.pinhole = {(*size)[0], (*size)[1], P(0, 0), P(1, 1), P(0, 2), P(1, 2)};
  auto model = Validated(intrinsics, file.string() + ": P_rect_" + i);
  if (!model) return model.status();
  return KittiRawCamera{*model, SE3()};
}

// The raw camera: K_0i, D_0i, S_0i, and X_cami = R_0i X_cam0 + T_0i.
Expected<KittiRawCamera> RawCamera(const KittiCalibValues& values, const std::string& i, const fs::path& file,
                                   SE3& T_cam0_camera) {
  auto size = ImageSize(values, "S_" + i, file);
  if (!size) return size.status();
  auto k = CalibNumbers(values, "K_" + i, 9, file);
  if (!k) return k.status();
  auto d = CalibNumbers(values, "D_" + i, 5, file);
  if (!d) return d.status();
  auto T_camera_cam0 = RigidTransform(values, "R_" + i, "T_" + i, file);
  if (!T_camera_cam0) return T_camera_cam0.status();
  T_cam0_camera = T_camera_cam0->inverse();
  PinholeRadtanIntrinsics intrinsics;
  intrinsics.pinhole = {(*size)[0], (*size)[1], (*k)[0], (*k)[4], (*k)[2], (*k)[5]};
  intrinsics.k1 = (*d)[0];
  intrinsics.k2 = (*d)[1];
  intrinsics.p1 = (*d)[2];
  intrinsics.p2 = (*d)[3];
  intrinsics.k3 = (*d)[4];
  auto model = Validated(intrinsics, file.string() + ": K_" + i + "/D_" + i);
  if (!model) return model.status();
  return KittiRawCamera{*model, SE3()};
}

}  // namespace

Expected<KittiRawRig> ReadKittiRawRig(const fs::path& date_folder) {
  auto imu_to_velo = ReadCalib(date_folder, "calib_imu_to_velo.txt");
  if (!imu_to_velo) return imu_to_velo.status();
  auto velo_to_cam = ReadCalib(date_folder, "calib_velo_to_cam.txt");
  if (!velo_to_cam) return velo_to_cam.status();
  auto T_velo_imu = RigidTransform(*imu_to_velo, "R", "T", date_folder / "calib_imu_to_velo.txt");
  if (!T_velo_imu) return T_velo_imu.status();
  auto T_cam0_velo = RigidTransform(*velo_to_cam, "R", "T", date_folder / "calib_velo_to_cam.txt");
  if (!T_cam0_velo) return T_cam0_velo.status();
  return KittiRawRig{T_velo_imu->inverse(), T_cam0_velo->inverse()};
}

Expected<KittiRawCamera> ReadKittiRawCamera(const fs::path& date_folder, const KittiRawRig& rig, int index,
                                            bool rectified) {
  auto values = ReadCalib(date_folder, "calib_cam_to_cam.txt");
  if (!values) return values.status();
  const fs::path file = date_folder / "calib_cam_to_cam.txt";
  const std::string i = std::to_string(index).insert(0, 1, '0');  // "02"
  SE3 T_cam0_camera;
  auto camera = rectified ? RectifiedCamera(*values, i, file, T_cam0_camera)
                          : RawCamera(*values, i, file, T_cam0_camera);
  if (!camera) return camera.status();
  camera->T_imu_camera = rig.T_imu_velo * rig.T_velo_cam0 * T_cam0_camera;
  return camera;
}

}  // namespace uf
