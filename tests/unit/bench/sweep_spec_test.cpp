// An accuracy sweep from what was asked for: its lists read from text, the device's defaults for
// what was not given, the checks that name the option at fault, and the named cases.

#include <penumbra/bench/sweep_spec.hpp>
#include <penumbra/scene/transfer_function.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace penumbra::bench {
namespace {

TEST(SweepSpec, CountsAreWholeNumbersInRangeEachOnce) {
    EXPECT_EQ(parse_counts("64,128,64").value(), (std::vector<int>{64, 128}));
    for (const char* bad : {"0", "1.5", "65537", "x", "64,x", ""}) {
        EXPECT_FALSE(parse_counts(bad).ok()) << bad;
    }
}

TEST(SweepSpec, DistancesAreFractionsOfTheUnitSortedEachOnce) {
    EXPECT_EQ(parse_distances("1/256, 1/512,1/256").value(),
              (std::vector<double>{1.0 / 512, 1.0 / 256}));
    for (const char* bad : {"0", "1.5", "-1/256", "x"}) {
        auto refused = parse_distances(bad);
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_EQ(refused.error().message,
                  "'" + std::string(bad) + "' is not a distance in (0, 1]");
    }
}

TEST(SweepSpec, LightsArePairsOfAngles) {
    EXPECT_EQ(parse_lights("10,45; 100,20").value(),
              (std::vector<quality::LightAngles>{{10.0, 45.0}, {100.0, 20.0}}));
    for (const char* bad : {"10", "10,45,3", "10,45;x,1"}) {
        EXPECT_FALSE(parse_lights(bad).ok()) << bad;
    }
}

TEST(SweepSpec, SwitchesAreOnOrOffEachOnceInTheOrderGiven) {
    EXPECT_EQ(parse_switches("off,on,off").value(), (std::vector<bool>{false, true}));
    EXPECT_EQ(parse_switches("on").value(), (std::vector<bool>{true}));
    EXPECT_EQ(parse_switches("yes").error().message, "'yes' is neither on nor off");
    EXPECT_FALSE(parse_switches("").ok());
}

TEST(SweepSpec, RefinementStepsLeaveTheStillOut) {
    EXPECT_EQ(parse_refinement_steps("8,0,2,8").value(), (std::vector<int>{2, 8}));
    EXPECT_TRUE(parse_refinement_steps("0").value().empty());
    for (const char* bad : {"-1", "1.5", "x", "100000"}) {
        EXPECT_FALSE(parse_refinement_steps(bad).ok()) << bad;
    }
}

TEST(SweepSpec, DefaultsAreValidListsAndASoftwareRasteriserGetsALighterSweep) {
    for (const bool gpu : {true, false}) {
        const SweepDefaults& d = sweep_defaults(gpu);
        EXPECT_TRUE(parse_lights(d.lights).ok());
        EXPECT_TRUE(parse_counts(d.slices).ok());
        EXPECT_TRUE(parse_counts(d.resolutions).ok());
        EXPECT_TRUE(parse_distances(d.sample_distances).ok());
    }
    EXPECT_LT(quality::frames_per_view(make_sweep({}, sweep_defaults(false)).value()),
              quality::frames_per_view(make_sweep({}, sweep_defaults(true)).value()));
}

TEST(SweepSpec, WhatIsNotGivenTakesTheDefaultsAndTheReferenceIsNeverASetting) {
    SweepSpec spec;
    spec.slices = std::vector<int>{16};
    spec.modes = std::vector<scene::Mode>{scene::Mode::reference, scene::Mode::sbrc};
    const quality::Sweep sweep = make_sweep(spec, sweep_defaults(false)).value();
    EXPECT_EQ(sweep.slices, (std::vector<int>{16}));
    EXPECT_EQ(sweep.modes, (std::vector<scene::Mode>{scene::Mode::sbrc}));
    EXPECT_EQ(sweep.resolutions, parse_counts(sweep_defaults(false).resolutions).value());
    EXPECT_EQ(sweep.repeat, sweep_defaults(false).repeat);
    const quality::Sweep every_mode = make_sweep({}, sweep_defaults(false)).value();
    EXPECT_EQ(every_mode.modes.size(), scene::modes().size() - 1);
}

TEST(SweepSpec, VolumesComeFromTheOptionTheCaseOrTheDefaultsWithTheHeadCt) {
    SweepSpec spec;
    spec.head_ct = "/cache/volumes/cranium_ct.nrrd";
    auto volumes = make_sweep(spec, sweep_defaults(false)).value().volumes;
    EXPECT_EQ(volumes.back(), "/cache/volumes/cranium_ct.nrrd");
    EXPECT_EQ(volumes.size(), 2U);
    spec.accuracy_case = find_accuracy_case("mri_brain");
    EXPECT_EQ(make_sweep(spec, sweep_defaults(false)).value().volumes,
              (std::vector<std::string>{"/usr/share/mricron/templates/ch2bet.nii.gz"}));
    spec.accuracy_case = find_accuracy_case("ct_soft_tissue");
    EXPECT_EQ(make_sweep(spec, sweep_defaults(false)).value().volumes,
              (std::vector<std::string>{"/cache/volumes/cranium_ct.nrrd"}));
    spec.head_ct.reset();
    EXPECT_EQ(make_sweep(spec, sweep_defaults(false)).error().where, "--case");
    spec.volumes = std::vector<std::string>{"a.nrrd"};
    EXPECT_EQ(make_sweep(spec, sweep_defaults(false)).value().volumes,
              (std::vector<std::string>{"a.nrrd"}));
}

TEST(SweepSpec, ChecksNameTheOptionAtFault) {
    SweepSpec spec;
    spec.repeat = 0;
    EXPECT_EQ(make_sweep(spec, sweep_defaults(true)).error().where, "--repeat");
    spec.repeat = 1;
    spec.refinement_steps = {4};
    EXPECT_EQ(make_sweep(spec, sweep_defaults(true)).error().where, "--refinement");
    spec.jitter = {false, true};
    EXPECT_TRUE(make_sweep(spec, sweep_defaults(true)).ok());
}

TEST(SweepSpec, AnUnknownCaseListsTheCases) {
    EXPECT_EQ(accuracy_case_named("mri_skin").value(), find_accuracy_case("mri_skin"));
    auto unknown = accuracy_case_named("bones");
    ASSERT_FALSE(unknown.ok());
    EXPECT_EQ(unknown.error().where, "--case");
    EXPECT_EQ(unknown.error().message,
              "no case 'bones' (cases: mri_skin, mri_brain, ct_bone, ct_soft_tissue)");
}

TEST(AccuracyCases, NameAPresetAndTheVolumesItSuits) {
    for (const char* name : {"mri_skin", "mri_brain", "ct_bone", "ct_soft_tissue"}) {
        const AccuracyCase* found = find_accuracy_case(name);
        ASSERT_NE(found, nullptr) << name;
        EXPECT_TRUE(scene::preset(found->transfer_function).ok()) << name;
    }
    EXPECT_TRUE(find_accuracy_case("ct_soft_tissue")->head_ct);
    EXPECT_TRUE(find_accuracy_case("ct_bone")->head_ct);
    EXPECT_EQ(find_accuracy_case("nothing"), nullptr);
}

}  // namespace
}  // namespace penumbra::bench
