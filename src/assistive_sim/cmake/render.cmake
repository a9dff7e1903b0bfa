# owned by the renderer engineer: assistive_sim_core, assistive_sim_nodelet, render_bag
