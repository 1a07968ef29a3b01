// Picking a pixel of a view: the point the eye sees there, in patient millimetres, with the scan's
// value (HU for a CT) and the label under it, on real data (the ch2 brain with the AAL atlas, the
// InVesalius head CT) and a synthetic scene whose answer is known.

#include <penumbra/reference/pick.hpp>
#include <penumbra/scene/camera.hpp>

#include <gtest/gtest.h>

#include <cstring>

namespace penumbra::reference {
namespace {

const std::filesystem::path templates = "/usr/share/mricron/templates";

scene::FrameRequest view_from(scene::View view, const char* preset) {
    scene::FrameRequest request;
    request.camera = scene::view_camera(view);
    request.settings.width = 64;
    request.settings.height = 64;
    request.transfer_function = scene::preset(preset).value();
    return request;
}

TEST(Pick, TheAalAtlasNamesTheRegionSeenAndHidingItPicksWhatLiesBehind) {
    auto brain = volume::load_volume(templates / "ch2bet.nii.gz");
    auto aal = volume::load_label_map(templates / "aal.nii.gz");
    ASSERT_TRUE(brain.ok() && aal.ok());
    scene::FrameRequest request = view_from(scene::View::left, "mri_skin");
    for (const volume::Label& label : aal->labels) {
        request.labels.styles.push_back({.id = label.id});
    }
    auto seen = pick(*brain, request, &*aal, 32, 32);
    ASSERT_TRUE(seen.ok()) << seen.error().to_string();
    ASSERT_TRUE(seen->hit);
    // From the left, the middle of the image is the left hemisphere's outer surface: AAL's left
    // labels end in _L, and the point lies well left of the midline.
    EXPECT_LT(seen->patient.x, -40.0);
    EXPECT_NE(seen->label_id, 0);
    EXPECT_TRUE(seen->label_name.ends_with("_L")) << seen->label_name;
    EXPECT_FALSE(seen->hounsfield);
    EXPECT_GT(seen->value, 0.0);

    // Hide it: the ray goes on into the brain, to another region, further right.
    for (scene::LabelStyle& style : request.labels.styles) {
        style.visible = style.id != seen->label_id;
    }
    auto behind = pick(*brain, request, &*aal, 32, 32);
    ASSERT_TRUE(behind.ok());
    ASSERT_TRUE(behind->hit);
    EXPECT_NE(behind->label_id, seen->label_id);
    EXPECT_GT(behind->patient.x, seen->patient.x + 1.0);

    // Outside the head: no hit. Outside the image: an error.
    auto corner = pick(*brain, request, &*aal, 0, 0);
    ASSERT_TRUE(corner.ok());
    EXPECT_FALSE(corner->hit);
    EXPECT_FALSE(pick(*brain, request, &*aal, 64, 10).ok());
    request.labels = {};
    auto unlabelled = pick(*brain, request, nullptr, 32, 32);
    ASSERT_TRUE(unlabelled.ok());
    EXPECT_EQ(unlabelled->label_id, 0);
    EXPECT_NEAR(unlabelled->patient.x, seen->patient.x, 1e-9);
}

TEST(Pick, ACtAnswersInHounsfieldUnitsOnBone) {
    auto ct = volume::load_volume(PENUMBRA_CRANIUM_CT);
    ASSERT_TRUE(ct.ok()) << ct.error().to_string();
    const scene::FrameRequest request = view_from(scene::View::anterior, "ct_bone");
    auto bone = pick(*ct, request, nullptr, 32, 28);
    ASSERT_TRUE(bone.ok()) << bone.error().to_string();
    ASSERT_TRUE(bone->hit);
    EXPECT_TRUE(bone->hounsfield);
    EXPECT_GT(bone->value, 150.0) << "ct_bone shows bone only";
    // Anterior view: the frontal bone lies in front of the head's middle.
    const volume::PatientBounds bounds = volume::patient_bounds(*ct);
    EXPECT_GT(bone->patient.y, 0.5 * (bounds.min.y + bounds.max.y));
}

}  // namespace
}  // namespace penumbra::reference
