// An accuracy sweep from what was asked for (see the header).

#include "penumbra/bench/sweep_spec.hpp"

#include <penumbra/base/text.hpp>
#include <penumbra/scene/frame_request.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra::bench {
namespace {

base::Error invalid(std::string message) {
    return base::make_error(base::ErrorCode::invalid_argument, std::move(message));
}

template <class T>
void sort_unique(std::vector<T>& values) {
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
}

// A list from text the parser accepts: the defaults, which are constants.
template <class T>
T parsed(base::Result<T> result) {
    return std::move(result).value();
}

constexpr SweepDefaults gpu_defaults{
        "/usr/share/mricron/templates/ch2.nii.gz,/usr/share/mricron/templates/ch2better.nii.gz,"
        "/usr/share/mricron/templates/inia19-t1-brain.nii.gz",
        "10,45;100,20;250,60",
        "32,64,128,256,512",
        "64,128,256,512,1024",
        "1/256,1/512",
        512,
        7};
constexpr SweepDefaults software_defaults{"/usr/share/mricron/templates/ch2.nii.gz",
                                          "10,45",
                                          "32,64,128,256",
                                          "64,128,256",
                                          "1/256",
                                          256,
                                          3};

}  // namespace

base::Result<std::vector<std::string>> sweep_volumes(const SweepSpec& spec,
                                                     const SweepDefaults& defaults) {
    if (spec.volumes) {
        return *spec.volumes;
    }
    const AccuracyCase* c = spec.accuracy_case;
    if (c != nullptr && c->head_ct) {
        if (!spec.head_ct) {
            return base::make_error(base::ErrorCode::not_found,
                                    std::string("case ") + c->name +
                                            " renders the head CT that scripts/demo-data.sh "
                                            "converts; run it, or name the CT with --volumes",
                                    "--case");
        }
        return std::vector<std::string>{spec.head_ct->string()};
    }
    if (c != nullptr && c->volumes != nullptr) {
        return base::split_list(c->volumes);
    }
    std::vector<std::string> volumes = base::split_list(defaults.volumes);
    if (spec.head_ct && c == nullptr) {
        volumes.push_back(spec.head_ct->string());
    }
    return volumes;
}

const std::vector<AccuracyCase>& accuracy_cases() {
    static const std::vector<AccuracyCase> cases = {
            {"mri_skin", "mri_skin", nullptr, false, "the MRI heads' opaque skin, where rays stop"},
            {"mri_brain", "mri_brain", "/usr/share/mricron/templates/ch2bet.nii.gz", false,
             "ch2bet, translucent grey and white matter"},
            {"ct_bone", "ct_bone", nullptr, true,
             "the head CT's skull, opaque bone over 1.5 mm slices"},
            {"ct_soft_tissue", "ct_soft_tissue", nullptr, true,
             "the head CT, translucent soft tissue"},
    };
    return cases;
}

const AccuracyCase* find_accuracy_case(std::string_view name) {
    for (const AccuracyCase& c : accuracy_cases()) {
        if (name == c.name) {
            return &c;
        }
    }
    return nullptr;
}

base::Result<std::vector<int>> parse_counts(std::string_view text) {
    const auto numbers = base::parse_numbers(text);
    std::vector<int> counts;
    for (const double number : numbers.ok() ? *numbers : std::vector<double>{}) {
        if (number < 1.0 || number > 65536.0 || std::floor(number) != number) {
            return invalid("expects whole numbers from 1 to 65536");
        }
        if (std::find(counts.begin(), counts.end(), int(number)) == counts.end()) {
            counts.push_back(static_cast<int>(number));
        }
    }
    if (counts.empty()) {
        return invalid("expects whole numbers from 1 to 65536");
    }
    return counts;
}

base::Result<std::vector<double>> parse_distances(std::string_view text) {
    std::vector<double> distances;
    for (const std::string& item : base::split_list(text)) {
        const auto number = base::parse_number(item);
        if (!number || !(*number > 0.0 && *number <= 1.0)) {
            return invalid("'" + item + "' is not a distance in (0, 1]");
        }
        distances.push_back(*number);
    }
    sort_unique(distances);
    return distances;
}

base::Result<std::vector<quality::LightAngles>> parse_lights(std::string_view text) {
    std::vector<quality::LightAngles> lights;
    for (const std::string& item : base::split_list(text, ';')) {
        const auto numbers = base::parse_numbers(item);
        if (!numbers || numbers->size() != 2) {
            return invalid("expects AZIMUTH,ELEVATION pairs separated by ';'");
        }
        lights.push_back({(*numbers)[0], (*numbers)[1]});
    }
    return lights;
}

base::Result<std::vector<bool>> parse_switches(std::string_view text) {
    std::vector<bool> switches;
    for (const std::string& item : base::split_list(text)) {
        if (item != "on" && item != "off") {
            return invalid("'" + item + "' is neither on nor off");
        }
        if (std::find(switches.begin(), switches.end(), item == "on") == switches.end()) {
            switches.push_back(item == "on");
        }
    }
    if (switches.empty()) {
        return invalid("expects on, off or on,off");
    }
    return switches;
}

base::Result<std::vector<int>> parse_refinement_steps(std::string_view text) {
    std::vector<int> steps;
    for (const std::string& item : base::split_list(text)) {
        const auto number = base::parse_number(item);
        const double value = number ? *number : -1.0;
        if (value != std::floor(value) || value < 0.0 || value > scene::kMaxRefinementSteps) {
            return invalid("'" + item + "' is not a step count in 0.." +
                           std::to_string(scene::kMaxRefinementSteps));
        }
        if (value > 0.0) {
            steps.push_back(static_cast<int>(value));
        }
    }
    sort_unique(steps);
    return steps;
}

const SweepDefaults& sweep_defaults(bool gpu_timers) {
    return gpu_timers ? gpu_defaults : software_defaults;
}

base::Result<quality::Sweep> make_sweep(const SweepSpec& spec, const SweepDefaults& defaults) {
    quality::Sweep sweep;
    sweep.lights = spec.lights ? *spec.lights : parsed(parse_lights(defaults.lights));
    if (spec.modes) {
        sweep.modes = *spec.modes;
    } else {
        for (const scene::ModeInfo& mode : scene::modes()) {
            sweep.modes.push_back(mode.mode);
        }
    }
    std::erase_if(sweep.modes, [](scene::Mode mode) { return scene::describe(mode).is_reference; });
    sweep.slices = spec.slices ? *spec.slices : parsed(parse_counts(defaults.slices));
    sweep.resolutions =
            spec.resolutions ? *spec.resolutions : parsed(parse_counts(defaults.resolutions));
    sweep.distances =
            spec.distances ? *spec.distances : parsed(parse_distances(defaults.sample_distances));
    sweep.repeat = spec.repeat.value_or(defaults.repeat);
    sweep.skipping = spec.skipping;
    sweep.jitter = spec.jitter;
    sweep.refinement_steps = spec.refinement_steps;
    if (sweep.repeat < 1 || sweep.repeat > 1000) {
        return base::make_error(base::ErrorCode::invalid_argument, "expects 1..1000", "--repeat");
    }
    if (!sweep.refinement_steps.empty() &&
        std::find(sweep.jitter.begin(), sweep.jitter.end(), true) == sweep.jitter.end()) {
        return base::make_error(base::ErrorCode::invalid_argument,
                                "refinement steps average jittered frames: add --jitter on or "
                                "--jitter off,on",
                                "--refinement");
    }
    auto volumes = sweep_volumes(spec, defaults);
    if (!volumes) {
        return volumes.error();
    }
    sweep.volumes = std::move(*volumes);
    return sweep;
}

base::Result<const AccuracyCase*> accuracy_case_named(std::string_view name) {
    if (const AccuracyCase* found = find_accuracy_case(name)) {
        return found;
    }
    std::string names;
    for (const AccuracyCase& c : accuracy_cases()) {
        names += (names.empty() ? "" : ", ") + std::string(c.name);
    }
    return base::make_error(base::ErrorCode::invalid_argument,
                            "no case '" + std::string(name) + "' (cases: " + names + ")", "--case");
}

}  // namespace penumbra::bench
