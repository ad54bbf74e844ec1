// `offsetmap demo`: every analysis on the default data, then the rendered room, into one folder.
#include <cstdio>

#include "cli.hpp"

namespace offsetmap::cli {
namespace {

struct DemoCli : Command {
    ReliefOptions relief;
    ShadingOptions shading;
    std::string out = "out/demo", data;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand(
            "demo",
            "compare + quick sweep + failure map + material frame on the default data, then the "
            "rendered room (frame/) and the error on its views (rendered/) -> one folder");
        shading.shadows = "soft";
        relief.add_to(*app, MapOption::Optional);
        shading.add_to(*app);
        app->add_option("-o,--out", out, "output folder")->capture_default_str();
        app->add_option("--data", data,
                        "folder of the default maps (default: the data/ found beside the "
                        "program)");
    }

    int run() override {
        if (data.empty()) data = default_data_dir();
        if (relief.height_map.empty()) relief.height_map = data + "/rocks.png";
        analyses();
        return rendered();
    }

  private:
    // The analyses on the plane scene and the data's maps.
    void analyses() {
        SceneOptions scene;
        scene.plane.width = 640;
        scene.plane.height = 360;
        run_compare(out, relief, shading, scene, 5);
        SweepCommand quick;
        quick.data_dir = data;
        quick.out_dir = out;
        quick.quick = true;
        run_sweep_command(quick, relief);
        FailureCommand fm;
        fm.out_dir = out;
        fm.samples = 128;
        run_failure_command(fm, relief);
        TemporalCommand tc;
        tc.out_dir = out;
        tc.frames = 12;
        run_temporal_command(tc, relief);
        // A frame of four materials (data/materials.json), three of them by error budget.
        MaterialsJob mj;
        mj.table = data + "/materials.json";
        mj.out_dir = out;
        mj.explain = true;
        ReliefOptions mrelief;
        mrelief.device = relief.device;
        ShadingOptions mshading;
        mshading.shadows = "soft";
        SceneOptions mscene;
        mscene.plane.width = 640;
        mscene.plane.height = 360;
        mscene.plane.camera_height = 0.9;  // high enough to see a dozen material tiles
        mscene.plane.pitch_deg = 28.0;
        run_materials_job(mj, mrelief, mshading, mscene);
    }

    // The rasterized room around the pass, deferred and forward (frame/), and the error on its
    // views (rendered/); without GL the rest of the demo stands.
    int rendered() {
        FrameCommand fc;
        fc.data_dir = data;
        fc.out_dir = out + "/frame";
        fc.width = 960;
        fc.height = 540;
        fc.forward = true;
        fc.shadows = "hard";
        fc.device = relief.device;
        try {
            run_frame(fc);
            // Error on real geometry (rendered/): the failure map over a rendered frame's
            // views, and a sweep on its G-buffer (the bricks everywhere, then the room's own
            // materials), on a frame small enough to sweep.
            FrameCommand small = fc;
            small.width = 320;
            small.height = 180;
            small.forward = false;
            small.repeats = 1;
            small.shadows = "none";
            small.out_dir = out + "/rendered";
            run_frame(small);
            FailureCommand rf;
            rf.out_dir = small.out_dir;
            rf.samples = 128;
            rf.gbuffer = small.out_dir + "/gbuffer.exr";
            run_failure_command(rf, relief);
            SweepCommand rs;
            rs.out_dir = small.out_dir;
            rs.gbuffer = rf.gbuffer;
            rs.maps = {data + "/rocks.png"};
            rs.materials = data + "/room.json";
            rs.methods = {"parallax", "steep", "relief", "pom", "cone", "exact"};
            rs.repeats = 3;
            return run_sweep_command(rs, relief);
        } catch (const UsageError&) {
            throw;
        } catch (const offsetmap::Error& e) {
            std::printf("demo: no rendered frame: %s\n", e.what());
            return 0;
        }
    }
};

}  // namespace

std::unique_ptr<Command> demo_command() { return std::make_unique<DemoCli>(); }

}  // namespace offsetmap::cli
