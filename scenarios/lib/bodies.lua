-- lib/bodies.lua: the family of bodies the transfer experiment and the tests run (docs/results.md,
-- "Transfer across bodies"; tests/test_body.cpp holds the same list): each a name and the
-- scenario parameters of lib/body.lua that make it. Together they span upper arms of 0.35-0.7 m,
-- forearms of 0.3-0.6 m, bases of 0.12-0.24 m, hands of 0.05-0.1 m, eyes of 32-256 pixels over
-- 60-120 degrees, and frozen eyes.
local bodies = {}

bodies.FAMILY = {
  { name = "long_arms", params = { upper_arm = 0.7, forearm = 0.6 } },
  { name = "short_arms", params = { upper_arm = 0.35, forearm = 0.3 } },
  { name = "wide_base", params = { base_radius = 0.24 } },
  { name = "small", params = { base_radius = 0.12, hand_radius = 0.05 } },
  { name = "big_hands", params = { upper_arm = 0.6, forearm = 0.45, hand_radius = 0.1 } },
  { name = "coarse_eyes", params = { eye_pixels = 32, eye_fov = 1.0472 } },
  { name = "wide_eyes", params = { eye_pixels = 256, eye_fov = 2.0944 } },
  { name = "frozen_eyes", params = { locked = "left_eye,right_eye" } },
}

return bodies
