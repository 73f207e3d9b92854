# corotational (Hauret, Salomon, Weiss & Wohlmuth): the paper's scenes through the driver (scenes/corot-*.yaml). The
# ball cases take about a second each, the two-plane, ellipse (0.1 s of it) and torus (0.2 s of it) cases a few.
stickslip_scene_tests(test_corot_scenes.py
  corot_ball_on_plane_model1 corot_ball_on_plane_model2 corot_ball_on_plane_friction_model1
  corot_ball_on_plane_friction_model2 corot_ball_on_plane_friction_nested corot_ball_on_plane_friction_dual
  corot_newton_vs_nonlinear corot_ball_two_planes corot_ball_two_planes_models corot_ellipse_two_planes
  corot_torus_on_plane corot_free_flight_momentum)
