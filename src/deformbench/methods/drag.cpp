#include "methods/drag.h"

#include <Eigen/Geometry>

#include "core/timer.h"

namespace db {

Mat4 interpolate_transform(const Mat4& T, double f) {
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  Mat4 P = Mat4::Identity();
  if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0) {
    const Eigen::AngleAxisd aa(R);
    P.topLeftCorner<3, 3>() = Eigen::AngleAxisd(f * aa.angle(), aa.axis()).toRotationMatrix();
  } else {
    P.topLeftCorner<3, 3>() = (1 - f) * Eigen::Matrix3d::Identity() + f * R;
  }
  P.topRightCorner<3, 1>() = f * T.topRightCorner<3, 1>();
  return P;
}

Points deform_frame(Deformer& d, const Edit& e, long long f, long long frames) {
  const long long given = e.target_frames();
  if (given == 0)
    return d.deform(interpolate_transform(e.transform, static_cast<double>(f) / static_cast<double>(frames)));
  const Eigen::Index h = e.count(Role::Handle);
  return d.deform_targets(e.targets.middleRows(((f - 1) % given) * h, h));
}

Drag drag(Deformer& d, const Edit& e, long long frames, const FrameDone& done) {
  Drag g;
  for (long long f = 1; f <= frames; ++f) {
    const CpuTimer cpu;
    g.V = deform_frame(d, e, f, frames);
    g.frame_cpu.push_back(cpu.seconds());
    const PhaseTimes& t = d.times();
    g.frame.push_back(t.frame());
    g.rhs.push_back(t.rhs);
    g.solve.push_back(t.solve);
    g.write.push_back(t.write);
    g.response.push_back(t.response);
    g.orthonormalize.push_back(t.orthonormalize);
    if (done) done(f);
  }
  return g;
}

}  // namespace db
