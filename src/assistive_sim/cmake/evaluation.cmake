# owned by the evaluation engineer: assistive_sim_eval, assistive_sim_bag, eval CLIs, import_dataset
