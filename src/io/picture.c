/* picture: placeholder, being written (issue 4). */
typedef int gr_placeholder_picture;
