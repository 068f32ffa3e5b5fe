/* fokker_planck: placeholder, being written (issue 5). */
