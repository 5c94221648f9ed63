#include "cogmap/mapping/evaluate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "cogmap/asr/room_metrics.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/text.h"
#include "cogmap/eval/plan_metrics.h"
#include "cogmap/eval/trajectory_metrics.h"
#include "cogmap/eval/wall_metrics.h"
#include "cogmap/io/image.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/draw/stages_picture.h"
#include "cogmap/io/world_io.h"
#include "cogmap/localize/heading_error.h"
#include "cogmap/plan/plan_json.h"

namespace cogmap::mapping {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

Evaluation EvaluateFolder(const std::string& dir_text, const EvaluateOptions& o) {
  // Unset (negative: what the folder recorded) or a range a sensor has (NaN
  // fell back to the folder's silently, infinity made every wall seeable).
  if (!(o.range_m < 0.0 || (o.range_m > 0.0 && o.range_m <= 1000.0)))
    throw InputError("--range " + Num(o.range_m) + ": must be in (0, 1000] metres");
  const std::filesystem::path dir(dir_text);
  const std::string walls_path = std::filesystem::is_directory(dir) ? (dir / "walls.json").string() : dir_text;
  const io::WallsFile wf = io::ReadWallsJson(walls_path);
  // Without a world (a real log with a reference trajectory, such as the
  // corrected CARMEN logs) only the heading errors and sizes can be scored.
  const bool have_world = !o.world.empty();
  io::WorldReadResult world;
  if (have_world) {
    world = io::ReadWorld(o.world);
    if (world.plan.walls.empty()) throw InputError(o.world, 0, "the world has no walls (LINES)");
  }
  // True rooms from a segmentation image, on the world's raster.
  RoomLabels room_labels;
  if (!o.rooms.empty()) {
    if (!have_world) throw InputError(o.rooms, 0, "the rooms image needs the world it segments (--world)");
    room_labels = io::ReadRoomSegmentation(o.rooms);
    const Vec2 extent(room_labels.width * room_labels.cell_m, room_labels.height * room_labels.cell_m);
    std::string ext = std::filesystem::path(o.world).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (ext == ".png" && (world.plan.max - extent).cwiseAbs().maxCoeff() > 0.5 * room_labels.cell_m)
      throw InputError(o.rooms, 0, "the rooms image covers " + Num(extent.x()) + " x " + Num(extent.y()) +
                                       " m, the world " + Num(world.plan.max.x()) + " x " + Num(world.plan.max.y()) +
                                       " m: not the same building's raster");
  }
  const bool label_rooms = !room_labels.empty();
  if (!wf.has_truth)
    throw InputError(wf.log_path, 0, "the log has no ground-truth poses: eval needs a run with truth "
                                     "(e.g. from cogmap simulate, or a corrected CARMEN log)");
  std::vector<Vec2> true_path;
  // The true path from the folder's store when there is one (the folder is
  // then self-contained: moved or copied, it evaluates without the log);
  // else (cogmap vectorize's folder) from the log. The store is read once:
  // its ASRs and their placements serve the room, heading, trajectory and
  // calibration metrics below.
  const std::filesystem::path store_path =
      std::filesystem::is_directory(dir) ? dir / "map.sqlite" : dir.parent_path() / "map.sqlite";
  const bool have_store = std::filesystem::exists(store_path);
  std::vector<asr::Asr> asrs;
  std::map<int, std::vector<Pose2>> placed_paths;
  std::map<int, Eigen::Matrix3d> covariances;
  std::vector<int> room_ids;  // per ASR of 'asrs': its physical room (revisits share one)
  if (have_store) {
    // Read only: works on a read-only folder or copy, and changes nothing.
    auto store = asr::SqliteAsrStore::Open(store_path.string(), asr::SqliteAsrStore::OpenMode::kReadOnly);
    for (int id : store->Ids())
      if (auto one = store->Get(id)) asrs.push_back(std::move(*one));
    for (const auto& x : asrs) {
      auto p = store->GetPlacement(x.id);
      room_ids.push_back(p ? p->room_id : x.id);
      if (p) {
        placed_paths[x.id] = std::move(p->corrected_path);
        covariances[x.id] = p->covariance;
      }
    }
    if (have_world)
      for (const auto& x : asrs)
        for (const auto& p : x.true_path) true_path.push_back(p.translation());
  }
  if (have_world && true_path.empty()) {
    auto log = io::OpenLog(wf.log_path, wf.log_format);
    sensors::LogRecord rec;
    while (log->Next(&rec))
      if (rec.truth) true_path.push_back(rec.truth->translation());
  }

  const auto map_walls = Transform(wf.world_from_map, wf.polylines);
  eval::WallMetricsOptions mo;
  mo.sensor_range_m = o.range_m > 0.0 ? o.range_m : (wf.sensor_range_m > 0.0 ? wf.sensor_range_m : 3.0);
  const auto prec = have_world ? eval::WallPrecision(map_walls, world.plan.walls, mo) : eval::PrecisionStats{};
  const auto rec_st = have_world ? eval::WallRecall(map_walls, world.plan.walls, true_path, mo) : eval::RecallStats{};

  if (!o.png.empty() && have_world) {
    draw::PictureOptions picture;
    picture.title = "Map walls over the true walls";
    draw::DrawWalls(map_walls, world.plan.walls, {}, picture).drawing.Write(o.png);
  }

  Evaluation out;
  nlohmann::json& j = out.metrics;
  // No map walls: precision is undefined (null), recall 0.
  if (prec.samples > 0) {
    j["wall_precision_mean_m"] = prec.mean_m;
    j["wall_precision_p95_m"] = prec.p95_m;
    j["wall_precision_max_m"] = prec.max_m;
  } else {
    j["wall_precision_mean_m"] = nullptr;
    j["wall_precision_p95_m"] = nullptr;
    j["wall_precision_max_m"] = nullptr;
  }
  if (have_world) {
    j["wall_recall"] = rec_st.recall();
  } else {
    j["wall_recall"] = nullptr;  // no world: nothing to compare the walls with
  }
  j["seeable_wall_length_m"] = rec_st.seeable_length_m;
  j["found_wall_length_m"] = rec_st.found_length_m;
  j["sensor_range_m"] = mo.sensor_range_m;
  j["map_samples"] = prec.samples;
  j["polylines"] = wf.polylines.size();
  j["vertex_count"] = wf.vertex_count;
  j["bytes_grid"] = wf.bytes_grid;
  j["bytes_vertices"] = wf.bytes_vertices;
  j["bytes_polylines"] = wf.bytes_polylines;
  j["polylines_over_grid"] = wf.bytes_grid > 0 ? static_cast<double>(wf.bytes_polylines) / wf.bytes_grid : 0.0;
  // A `cogmap map` folder: the ASRs add the room and heading metrics.
  std::optional<asr::RoomMetrics> rooms;
  std::optional<localize::HeadingErrorStats> headings;
  std::optional<eval::TrajectoryMetrics> trajectory;
  std::optional<eval::PoseCalibration> calibration;
  if (have_store) {
    rooms = label_rooms ? asr::EvaluateRooms(asrs, room_labels) : asr::EvaluateRooms(asrs, world.plan.rooms);
    j["asr_count"] = rooms->asr_count;
    if (have_world && (label_rooms || !world.plan.rooms.empty())) {
      j["room_precision"] = rooms->room_precision;
      j["room_recall"] = rooms->room_recall;
      std::vector<int> ids;
      for (const auto& x : asrs) ids.push_back(x.id);
      const asr::RevisitMetrics rv = asr::EvaluateRevisits(ids, room_ids, rooms->asr_room);
      j["graph_rooms"] = rv.graph_rooms;
      j["revisits"] = rv.revisits;
      j["revisits_right"] = rv.revisits_right;
      j["revisits_wrong"] = rv.revisits_wrong;
    } else {
      j["room_precision"] = nullptr;  // the world has no ground-truth Room areas
      j["room_recall"] = nullptr;
      j["graph_rooms"] = j["revisits"] = j["revisits_right"] = j["revisits_wrong"] = nullptr;
    }
    headings = localize::ComputeHeadingErrors(asrs, placed_paths);
    for (const auto& [key, value] : localize::HeadingErrorEvalKeys(*headings)) j[key] = value;
    // ATE/RPE of the corrected and the raw trajectories against the log's
    // reference poses (the same with or without a world: ATE aligns once, RPE
    // is frame-free).
    const eval::AsrTrajectories traj = eval::PairAsrTrajectories(asrs, placed_paths);
    trajectory = eval::ComputeTrajectoryMetrics(traj);
    for (const auto& [key, value] : eval::TrajectoryEvalKeys(*trajectory)) {
      if (value) j[key] = *value;
      else j[key] = nullptr;
    }
    // The walls once more after the ATE's one rigid alignment of the path
    // (the map's shape, whatever its frame: a heading error made before the
    // first walls were seen turns the whole map about its start, which
    // wall_precision_* counts and no later wall can see). The unaligned keys
    // stay the figures; these say how much of them is that turn.
    if (have_world && trajectory->ate.poses > 0 && prec.samples > 0) {
      const Pose2& a = trajectory->ate.reference_from_estimate;
      const auto aligned = eval::WallPrecision(Transform(a, wf.polylines), world.plan.walls, mo);
      j["wall_precision_p95_m_aligned"] = aligned.p95_m;
      j["wall_precision_mean_m_aligned"] = aligned.mean_m;
      // The alignment against the frame the map was put in (world_from_map).
      const Pose2 turn = a * wf.world_from_map.inverse();
      j["map_alignment_deg"] = RadToDeg(NormalizeAngle(turn.theta));
      j["map_alignment_m"] = std::hypot(turn.x, turn.y);
    }
    // Calibration of the pose graph's covariances (issue 10): the ASRs the
    // graph placed with a covariance, against their true frame poses.
    calibration = eval::ComputePoseCalibration(asrs, covariances);
    for (const auto& [key, value] : eval::PoseCalibrationEvalKeys(*calibration)) {
      if (value) j[key] = *value;
      else j[key] = nullptr;
    }
  }
  // The floor plan (issue 11), when the folder has one: in the world frame
  // through walls.json's world_from_map, as the walls are.
  std::optional<eval::PlanMetrics> plan_metrics;
  const std::filesystem::path plan_path = std::filesystem::is_directory(dir) ? dir / "plan.json" : dir.parent_path() / "plan.json";
  if (std::filesystem::exists(plan_path)) {
    const plan::Plan fp = plan::TransformPlan(wf.world_from_map, plan::ReadPlanJson(plan_path.string()));
    eval::PlanMetricsOptions po;
    po.sensor_range_m = mo.sensor_range_m;
    plan_metrics = have_world ? eval::EvaluatePlan(fp, world.plan, true_path, po, label_rooms ? &room_labels : nullptr)
                              : eval::DescribePlan(fp);
    for (const auto& [key, value] : eval::PlanEvalKeys(*plan_metrics, have_world)) {
      if (value) j[key] = *value;
      else j[key] = nullptr;
    }
    if (have_world && world.plan.rooms.empty() && !label_rooms)  // no true rooms
      j["room_iou_median"] = j["rooms_entered"] = j["room_iou_median_entered"] = nullptr;
  }
  j["mode"] = wf.mode;
  j["log"] = wf.log_path;
  if (have_world) j["world"] = o.world; else j["world"] = nullptr;
  {
    AppendF(&out.text, "%s vs %s (%s mode)\n", walls_path.c_str(), have_world ? o.world.c_str() : "(no world: headings only)",
                wf.mode.c_str());
    if (!have_world)
      ;
    else if (prec.samples > 0)
      AppendF(&out.text, "  wall precision: mean %.3f m, p95 %.3f m, max %.3f m (%lld samples)\n", prec.mean_m, prec.p95_m,
                  prec.max_m, static_cast<long long>(prec.samples));
    else
      AppendF(&out.text, "  wall precision: n/a (the map has no walls)\n");
    if (have_world) AppendF(&out.text, "  wall recall: %.3f (%.1f of %.1f m seeable within %.1f m of the true path)\n", rec_st.recall(),
                rec_st.found_length_m, rec_st.seeable_length_m, mo.sensor_range_m);
    AppendF(&out.text, "  %zu polylines, %lld vertices; bytes grid %lld, vertices %lld, polylines %lld (%.2f%% of grid)\n",
                wf.polylines.size(), static_cast<long long>(wf.vertex_count), static_cast<long long>(wf.bytes_grid),
                static_cast<long long>(wf.bytes_vertices), static_cast<long long>(wf.bytes_polylines),
                100.0 * j["polylines_over_grid"].get<double>());
    if (rooms) {
      if (have_world) AppendF(&out.text, "  %d ASRs; rooms: precision %.3f, recall %.3f (%d of %d rooms matched)\n", rooms->asr_count,
                  rooms->room_precision, rooms->room_recall, rooms->matched_rooms, rooms->room_count);
      if (have_world && j["revisits"].is_number())
        AppendF(&out.text, "  %d physical rooms in the store; revisits %d (right %d, wrong %d)\n",
                j["graph_rooms"].get<int>(), j["revisits"].get<int>(), j["revisits_right"].get<int>(),
                j["revisits_wrong"].get<int>());
    }
    if (plan_metrics) {
      const auto& pm = *plan_metrics;
      AppendF(&out.text, "  floor plan: %d walls (%.1f m, %.2f vertices/m), %d rooms, %d doors; room overlap %.2f m2\n", pm.walls,
                  pm.wall_length_m, pm.vertices_per_m, pm.rooms, pm.doors, pm.room_overlap_m2);
      if (have_world && pm.precision_p95_m)
        AppendF(&out.text, "  floor-plan walls: precision p50 %.3f m, p95 %.3f m; recall %.3f; duplication %s; "
                    "room IoU median %s (%s over the %d of %zu rooms the robot entered)\n",
                    *pm.precision_p50_m, *pm.precision_p95_m, pm.recall,
                    pm.duplication ? Num(*pm.duplication).c_str() : "n/a",
                    pm.room_iou_median && (label_rooms || !world.plan.rooms.empty()) ? Num(*pm.room_iou_median).c_str()
                                                                                    : "n/a",
                    pm.room_iou_median_entered ? Num(*pm.room_iou_median_entered).c_str() : "n/a", pm.rooms_entered,
                    pm.room_iou.size());
    }
    if (j.contains("heading_error_deg_median")) {
      AppendF(&out.text, "  heading error (deg, one global rotation removed): corrected median %.2f, max %.2f; "
                  "raw median %.2f, max %.2f\n",
                  j["heading_error_deg_median"].get<double>(), j["heading_error_deg_max"].get<double>(),
                  j["heading_error_deg_median_raw"].get<double>(), j["heading_error_deg_max_raw"].get<double>());
    }
    if (j.contains("odometry_drift_deg_per_m"))
      AppendF(&out.text, "  the odometry's heading drift against the truth: %.3f deg/m (report.json has the map's estimate)\n",
              j["odometry_drift_deg_per_m"].get<double>());
    if (trajectory && trajectory->ate.poses > 0) {
      const auto& t = *trajectory;
      AppendF(&out.text, "  trajectory (%d poses): ATE RMSE corrected %.3f m (median %.3f, max %.3f), raw %.3f m "
                  "(median %.3f, max %.3f)\n",
                  t.ate.poses, t.ate.rmse_m, t.ate.median_m, t.ate.max_m, t.ate_raw.rmse_m, t.ate_raw.median_m,
                  t.ate_raw.max_m);
      std::string line = "  RPE RMSE corrected / raw:";
      for (size_t k = 0; k < t.rpe.size(); ++k) {
        line += " " + Num(eval::TrajectoryDistances()[k]) + " m: ";
        if (!t.rpe[k]) {
          line += "n/a;";
          continue;
        }
        char buf[160];
        std::snprintf(buf, sizeof buf, "%.3f / %.3f m, %.2f / %.2f deg;", t.rpe[k]->trans_rmse_m,
                      t.rpe_raw[k]->trans_rmse_m, t.rpe[k]->rot_rmse_deg, t.rpe_raw[k]->rot_rmse_deg);
        line += buf;
      }
      line.pop_back();
      AppendF(&out.text, "%s\n", line.c_str());
    }
    if (calibration && calibration->checked() > 0) {
      const auto& c = *calibration;
      AppendF(&out.text, "  pose calibration: %d of %d placed ASRs within 3 sigma of the truth (position %d, heading %d; "
                  "relative to ASR %d)\n",
                  c.within(), c.checked(), c.position_within(), c.heading_within(), c.reference_asr);
    }
  }
  return out;
}

}  // namespace cogmap::mapping
