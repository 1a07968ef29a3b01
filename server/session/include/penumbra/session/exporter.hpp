#pragma once

// Pictures to keep: a session's view as a still larger than its frames may be (up to
// ExportLimits::max_side a side), or a movie of it turning (a turntable), rendered in tiles at the
// lowest priority so that no session's frames wait for it, each tile refined as the session's
// stills are, put together into a PNG that carries what drew it or an MP4, and held for download
// for a while.

#include <penumbra/base/result.hpp>
#include <penumbra/encode/encode.hpp>
#include <penumbra/session/scheduler.hpp>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace penumbra::session {

struct ExportLimits {
    int max_side = 4096;  // a still's largest side
    int max_movie_side = 1920;
    int max_movie_frames = 720;
    int per_client = 1;  // exports a client may have running at a time
    int at_once = 2;     // exports running at a time, all clients together
    // Tiles are at most this large a side: any session's frame preempts an export's tile, which
    // then starts again, so a small tile loses little and an export goes on between frames.
    int tile_side = 1024;
    // A finished export can be downloaded this long; the oldest goes first when those kept would
    // hold more than max_bytes_kept.
    std::chrono::seconds kept{900};
    std::size_t max_bytes_kept = std::size_t{256} << 20;
    // An export that has not finished in this long fails (a busy server preempts its tiles
    // again and again), giving its place back.
    std::chrono::seconds longest{900};
    std::chrono::seconds longest_movie{3600};
    // A movie is at most this part of what is kept, so that one does not push every other
    // client's downloads out.
    int movie_share_of_kept = 4;  // 1/4
};

enum class ExportState { running, done, failed, cancelled };

std::string_view to_string(ExportState state);

// Where an export stands, as its progress callback hears it.
struct ExportStatus {
    std::string id;  // 128 random bits in hex: whoever knows it may download the export
    ExportState state = ExportState::running;
    double progress = 0.0;  // 0..1
    int width = 0;
    int height = 0;
    int tiles = 0;          // the tiles the still (each movie frame) is rendered in (more if one
                            // did not fit)
    int frames = 0;         // a movie's
    std::size_t bytes = 0;  // the file's, when done
    std::string file_name;  // what a download saves it as
    std::optional<base::Error> error;  // why it failed
};

// A turntable: `frames` views turned about the view's up axis through the camera's target, a
// whole turn, or rocking between -rock and +rock degrees (scene::turntable_degrees).
struct MovieSpec {
    int frames = 0;
    double rock = 0.0;
    int frames_per_second = 30;
    int quality = 20;  // x264's rate factor (encode::MovieOptions)
};

// A finished export, as a download serves it.
struct ExportFile {
    std::shared_ptr<const std::vector<std::uint8_t>> bytes;
    std::string file_name;
    std::string content_type;
};

class Exporter {
public:
    // Called from the export's thread on every change of its status, the last time with a state
    // other than running; it must only hand the status on.
    using Progress = std::function<void(const ExportStatus&)>;

    Exporter(Scheduler& scheduler, ExportLimits limits);
    Exporter(const Exporter&) = delete;
    Exporter& operator=(const Exporter&) = delete;
    // Cancels what runs and waits for it; before the scheduler it renders through goes.
    ~Exporter();

    // Cancels what runs and waits for it (their last statuses said): before the connections they
    // report to go.
    void shutdown();

    [[nodiscard]] const ExportLimits& limits() const { return limits_; }

    // Starts rendering `still` (a session's still job, Session::make_job, its request at the
    // export's size) as a PNG named `file_name`, keeping the volume's name `source` and the state
    // that drew it (`state_json`) in it (encode::still_text). Tiles are as large as a
    // frame may be (`max_tile_side`, and at most limits().tile_side) and shrink where one asks
    // for more work than a frame may.
    // Errors: out_of_range (a side beyond max_side), rate_limited (the client's or the server's
    // exports all running).
    base::Result<std::string> start_still(const std::string& client, RenderJob still,
                                          int max_tile_side, std::string file_name,
                                          const std::string& source, const std::string& state_json,
                                          Progress progress);

    // Starts rendering `movie`: each frame `still` turned by its angle, into an MP4 (its sides
    // even, at most limits().max_movie_side, and at most limits().max_movie_frames frames), every
    // frame refined with the steps the first needed (lest the grain change from frame to frame).
    // Errors as start_still's, and invalid_value for an odd side.
    base::Result<std::string> start_movie(const std::string& client, RenderJob still,
                                          MovieSpec movie, int max_tile_side, std::string file_name,
                                          Progress progress);

    // Stops `client`'s export `id`, which then reports `cancelled`; false when there is no such
    // export running.
    bool cancel(const std::string& id, const std::string& client);

    // A finished export that is still kept.
    [[nodiscard]] std::optional<ExportFile> file(const std::string& id);

    // Exports running now.
    [[nodiscard]] int running() const;
    [[nodiscard]] bool is_running(const std::string& id) const;

private:
    struct Job;

    void run(const std::shared_ptr<Job>& job);
    // Renders one frame of the job at the lowest priority and waits for it; cancelled when the
    // job is.
    base::Result<std::shared_ptr<const base::ImageRgba8>> render(const std::shared_ptr<Job>& job,
                                                                 RenderJob frame);

    // `still` and its refinement steps until a step changes the image by no more than
    // `threshold` or `most_steps` (scene::refines_after); `stepped` hears of each step but the
    // last.
    struct Refined {
        std::shared_ptr<const base::ImageRgba8> image;
        int steps = 0;
    };

    base::Result<Refined> refine(const std::shared_ptr<Job>& job, const scene::FrameRequest& still,
                                 int most_steps, double threshold,
                                 const std::function<void(int)>& stepped);

    // `view` in tiles of `tile_side`, each refined `steps` times; `threshold` > 0 stops a view of
    // one tile where its image stops changing, and sets the steps of a view of several by a probe
    // of it at a tile's size. `progressed` hears how much of the view is done (0..1).
    struct ViewRendered {
        base::ImageRgba8 image;
        int steps = 0;  // the refinement steps each tile took
    };

    base::Result<ViewRendered> render_view(const std::shared_ptr<Job>& job,
                                           const scene::FrameRequest& view, int tile_side,
                                           int steps, double threshold,
                                           const std::function<void(double)>& progressed);
    base::Result<ExportFile> make_still(const std::shared_ptr<Job>& job, int tile_side);
    base::Result<ExportFile> make_movie(const std::shared_ptr<Job>& job, int tile_side);
    base::Result<std::string> start(std::shared_ptr<Job> job);
    void keep(const std::string& id, ExportFile file);
    void finish(Job& job, ExportStatus status);

    Scheduler& scheduler_;
    ExportLimits limits_;
    mutable std::mutex mutex_;
    std::map<std::string, std::shared_ptr<Job>> running_;
    std::condition_variable idle_;  // an export finished

    struct Kept {
        ExportFile file;
        std::chrono::steady_clock::time_point until;
    };

    std::map<std::string, Kept> kept_;
    std::vector<std::thread> threads_;
};

}  // namespace penumbra::session
